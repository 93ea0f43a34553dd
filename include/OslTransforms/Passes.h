//===- Passes.h - osl-mlir passes -------------------------------*- C++ -*-===//
#ifndef OSLTRANSFORMS_PASSES_H
#define OSLTRANSFORMS_PASSES_H

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/Dialect/ControlFlow/IR/ControlFlow.h"
#include "mlir/Dialect/Func/IR/FuncOps.h"
#include "mlir/Dialect/LLVMIR/LLVMDialect.h"
#include "mlir/Dialect/Math/IR/Math.h"
#include "mlir/Dialect/SCF/IR/SCF.h"
#include "mlir/Dialect/Vector/IR/VectorOps.h"
#include "mlir/Pass/Pass.h"
#include "mlir/Pass/PassManager.h"

namespace mlir::osl {

#define GEN_PASS_DECL
#include "OslTransforms/Passes.h.inc"

/// The whole chain from front-end output to the LLVM dialect at `width`.
/// `reference`: one point at a time with ordinary branches (width 1, no
/// masks), the oracle of the differential tester. `countLanes`: masked
/// blocks report their active lanes (osl-run --lane-stats).
void buildOslToLLVMPipeline(OpPassManager &pm, int width,
                            const std::string &paramValues = "", bool reference = false,
                            bool countLanes = false);

/// Registers every pass and the `osl-to-llvm` pipeline with mlir-opt style
/// tools.
void registerOslPasses();

#define GEN_PASS_REGISTRATION
#include "OslTransforms/Passes.h.inc"

} // namespace mlir::osl

#endif // OSLTRANSFORMS_PASSES_H
