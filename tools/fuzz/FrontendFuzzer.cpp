//===- FrontendFuzzer.cpp - libFuzzer target: OSL source to kernel IR -----===//
//
// Any byte string is an OSL source file: the front end must either reject
// it with diagnostics or produce a module that verifies and that the whole
// osl-to-llvm pipeline (width 4) either lowers or rejects with a
// diagnostic. Crashes, hangs and sanitizer reports are the findings.
//
//===----------------------------------------------------------------------===//
#include "OslDialect/OslDialect.h"
#include "OslFrontend/Frontend.h"
#include "OslPipeline/Pipeline.h"

#include "mlir/IR/Diagnostics.h"
#include "mlir/IR/Verifier.h"
#include "mlir/Pass/PassManager.h"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  mlir::MLIRContext context;
  context.disableMultithreading();
  // Diagnostics from the passes are expected for odd shaders; drop them.
  mlir::ScopedDiagnosticHandler quiet(&context, [](mlir::Diagnostic &) {
    return mlir::success();
  });
  std::string source(reinterpret_cast<const char *>(data), size); // NUL-terminated
  std::string errors;
  llvm::raw_string_ostream errs(errors);
  mlir::OwningOpRef<mlir::ModuleOp> module =
      osl::parseOslShader(source, "fuzz.osl", context, {}, errs);
  if (!module)
    return 0;
  if (mlir::failed(mlir::verify(*module)))
    __builtin_trap(); // the front end must only emit valid IR
  mlir::PassManager pm(&context);
  mlir::osl::OslToLLVMPipelineOptions pipeline;
  pipeline.width = 4;
  mlir::osl::buildOslToLLVMPipeline(pm, pipeline);
  (void)pm.run(*module);
  return 0;
}
