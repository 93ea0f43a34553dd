//===- GroupInputs.h - Mark a layer's connected inputs ----------*- C++ -*-===//
#ifndef OSLCOMPILER_GROUPINPUTS_H
#define OSLCOMPILER_GROUPINPUTS_H

#include "OslCompiler/ShaderGroup.h"

#include "mlir/Dialect/Func/IR/FuncOps.h"
#include "llvm/Support/raw_ostream.h"

namespace osl {

/// Marks the parameters of one layer's shader function that the group
/// connects (osl.connect = [layer, output], for osl-link-group) or declares
/// as userdata, as testshade names them: a struct input field by field
/// (IN.f from OUT.f), a component of a triple input (IN[k]) as a float
/// parameter of its own inserted into the triple. Each name must be a
/// parameter; false after an error printed to `errs`.
bool markGroupInputs(mlir::func::FuncOp func, const GroupLayer &layer, const ShaderGroup &group,
                     const std::string &shaderName, llvm::raw_ostream &errs);

} // namespace osl

#endif // OSLCOMPILER_GROUPINPUTS_H
