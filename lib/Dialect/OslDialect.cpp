//===- OslDialect.cpp - The osl dialect -----------------------------------===//
#include "OslDialect/OslDialect.h"

#include "mlir/IR/Builders.h"
#include "mlir/IR/DialectImplementation.h"
#include "llvm/ADT/TypeSwitch.h"

using namespace mlir;
using namespace mlir::osl;

#include "OslDialect/OslOpsDialect.cpp.inc"
#include "OslDialect/OslEnums.cpp.inc"

#define GET_TYPEDEF_CLASSES
#include "OslDialect/OslOpsTypes.cpp.inc"

void OslDialect::initialize() {
  addOperations<
#define GET_OP_LIST
#include "OslDialect/OslOps.cpp.inc"
      >();
  addTypes<
#define GET_TYPEDEF_LIST
#include "OslDialect/OslOpsTypes.cpp.inc"
      >();
}
