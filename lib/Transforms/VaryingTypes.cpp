//===- VaryingTypes.cpp - Moving values from uniform to varying -----------===//
#include "VaryingTypes.h"

#include "OslDialect/OslDialect.h"

#include "llvm/ADT/SmallVector.h"

using namespace mlir;
using namespace mlir::osl;

bool mlir::osl::makeVarying(Value v) {
  if (isVarying(v.getType()))
    return false;
  v.setType(VaryingType::get(v.getType()));
  return true;
}

bool mlir::osl::isDataOp(Operation *op) {
  return op->getDialect() && isa<OslDialect>(op->getDialect()) &&
         op->getNumRegions() == 0 && op->getNumResults() > 0 &&
         !isa<GlobalOp, BatchMaskOp, AnyOp, IsConstantOp>(op);
}

void mlir::osl::makeDataUsersVarying(ValueRange values) {
  SmallVector<Value> work;
  for (Value v : values)
    if (isVarying(v.getType()))
      work.push_back(v);
  while (!work.empty()) {
    Value v = work.pop_back_val();
    for (Operation *user : v.getUsers())
      if (isDataOp(user))
        for (Value r : user->getResults())
          if (makeVarying(r))
            work.push_back(r);
  }
}
