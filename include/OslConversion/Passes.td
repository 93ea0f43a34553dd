//===- Passes.td - osl-mlir conversions --------------------*- tablegen -*-===//
//
// The two conversions that take an osl function to an LLVM-dialect batch
// kernel (lib/Conversion).
//
//===----------------------------------------------------------------------===//
#ifndef OSL_CONVERSION_PASSES_TD
#define OSL_CONVERSION_PASSES_TD

include "mlir/Pass/PassBase.td"

def ConvertToVector : Pass<"osl-convert-to-vector", "::mlir::ModuleOp"> {
  let summary = "Lower the osl dialect to vector code of a chosen width";
  let description = [{
    Varying values become vector<W x T> (triples vector<3 x W x f32>),
    uniform values stay scalar. The shader becomes the batch kernel
    `void @osl_batch(ptr globals, ptr outputs, i32 nactive)` of
    OslAbi/GlobalsLayout.h; library calls become arith/math/vector ops.
  }];
  let options = [Option<"referenceMode", "reference", "bool", "false",
                        "every value is uniform (osl-uniform-reference): keep their "
                        "derivatives">,
                 Option<"width", "width", "int", "8",
                        "lanes per batch: 1, 4, 8 or 16">,
                 Option<"assumeCompiled", "assume-compiled", "bool", "false",
                        "take every noise routine as compiled already: only those "
                        "a call needs the code of are built (the compiler asks its "
                        "library objects instead)">];
  let dependentDialects = ["::mlir::arith::ArithDialect", "::mlir::math::MathDialect",
                           "::mlir::vector::VectorDialect", "::mlir::scf::SCFDialect",
                           "::mlir::LLVM::LLVMDialect"];
}

def LowerToLLVM : Pass<"osl-lower-to-llvm", "::mlir::ModuleOp"> {
  let summary = "Lower vector/arith/math/scf code to the LLVM dialect";
  let description = [{
    Math functions become polynomial approximations that stay in vector
    registers (no per-lane libm calls), then everything becomes LLVM. Vector
    int / and % by divisors that are not one constant divide in double
    precision, exactly (x86 has no vector integer division).
  }];
  let dependentDialects = ["::mlir::LLVM::LLVMDialect", "::mlir::cf::ControlFlowDialect",
                           "::mlir::arith::ArithDialect", "::mlir::math::MathDialect",
                           "::mlir::vector::VectorDialect"];
}

#endif // OSL_CONVERSION_PASSES_TD
