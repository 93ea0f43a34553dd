//===- osl-opt.cpp - mlir-opt for the osl dialect and its passes ---------===//
//
// Registers only the dialects the pipeline produces (registering all of
// MLIR costs ~37 s of compile time and 2.6 GB) and every osl pass.
//
//===----------------------------------------------------------------------===//
#include "OslDialect/OslDialect.h"
#include "OslPipeline/Pipeline.h"

#include "mlir/Dialect/ControlFlow/IR/ControlFlow.h"
#include "mlir/IR/DialectRegistry.h"
#include "mlir/Tools/mlir-opt/MlirOptMain.h"
#include "mlir/Transforms/Passes.h"

int main(int argc, char **argv) {
  mlir::DialectRegistry registry;
  registry.insert<mlir::osl::OslDialect, mlir::func::FuncDialect,
                  mlir::arith::ArithDialect, mlir::math::MathDialect,
                  mlir::scf::SCFDialect, mlir::vector::VectorDialect,
                  mlir::cf::ControlFlowDialect, mlir::LLVM::LLVMDialect>();
  mlir::osl::registerOslPasses();
  mlir::registerCanonicalizerPass();
  mlir::registerCSEPass();
  // Upstream passes that work through RegionBranchOpInterface, which
  // osl.if and osl.while implement.
  mlir::registerControlFlowSinkPass();
  return mlir::asMainReturnCode(
      mlir::MlirOptMain(argc, argv, "osl-mlir optimizer driver\n", registry));
}
