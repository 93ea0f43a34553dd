//===- VaryingTypes.h - Moving values from uniform to varying --*- C++ -*-===//
//
// Private to lib/Transforms: the data-dependence rule of
// osl-varying-propagation, for passes that make a value varying before it
// runs (osl-unroll-constant-loops replaces a loop's uniform-typed results by
// the varying values its trips computed).
//
//===----------------------------------------------------------------------===//
#ifndef OSLTRANSFORMS_VARYINGTYPES_H
#define OSLTRANSFORMS_VARYINGTYPES_H

#include "mlir/IR/ValueRange.h"

namespace mlir::osl {

/// Makes `v` varying; true if that changed it.
bool makeVarying(Value v);

/// Ops whose results depend only on their operands (is_constant answers
/// one uniform 0 or 1 however its operand varies).
bool isDataOp(Operation *op);

/// Makes varying the results of the data ops that read `values` (now
/// varying) and, in turn, of those that read them: a result typed from
/// operands (osl.deriv's is its value's type) follows them.
void makeDataUsersVarying(ValueRange values);

} // namespace mlir::osl

#endif // OSLTRANSFORMS_VARYINGTYPES_H
