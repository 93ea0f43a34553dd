//===- Frontend.cpp - OSL source to the osl dialect ---------------------------===//
#include "OslFrontend/Frontend.h"

#include "IRGen.h"
#include "OslLanes/ColorBuilder.h"
#include "Parser.h"
#include "Preprocessor.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/Dialect/Func/IR/FuncOps.h"
#include "mlir/IR/Diagnostics.h"
#include "mlir/IR/Verifier.h"

using namespace osl::frontend;

mlir::OwningOpRef<mlir::ModuleOp>
osl::parseOslShader(llvm::StringRef source, llvm::StringRef filename,
                    mlir::MLIRContext &context, llvm::ArrayRef<ParamOverride> overrides,
                    llvm::raw_ostream &errs, const FrontendOptions &options) {
  context.loadDialect<mlir::osl::OslDialect, mlir::func::FuncDialect,
                      mlir::arith::ArithDialect>();
  Diagnostics diags(filename, errs);
  diags.setWarningMode(options.warningsAsErrors ? WarningMode::AsErrors
                       : options.showWarnings   ? WarningMode::Show
                                                : WarningMode::Hide);
  if (!mlir::osl::ColorSystem::get(options.colorSpace)) {
    diags.error("unknown color space '" + options.colorSpace +
                "' (known: Rec709, sRGB, NTSC, EBU, PAL, SECAM, SMPTE, HDTV, CIE, AdobeRGB, "
                "XYZ, ACES2065-1, ACEScg)");
    return nullptr;
  }
  std::vector<Token> tokens;
  if (!lexAndPreprocess(source, diags, tokens, options.includePaths, options.defines))
    return nullptr;
  Program program;
  if (!parseProgram(tokens, diags, program))
    return nullptr;
  IRGen gen(context, diags, overrides, options);
  mlir::OwningOpRef<mlir::ModuleOp> module = gen.emitProgram(program);
  if (!module || diags.hadError())
    return nullptr;
  // The emitter should only produce valid IR; report it if not.
  std::string verifyMessages;
  {
    llvm::raw_string_ostream os(verifyMessages);
    mlir::ScopedDiagnosticHandler handler(&context, [&](mlir::Diagnostic &d) {
      os << d.getLocation() << ": " << d << "\n";
      return mlir::success();
    });
    if (mlir::failed(mlir::verify(*module))) {
      diags.error("internal error: the generated IR does not verify:\n" + verifyMessages);
      return nullptr;
    }
  }
  return module;
}

std::string osl::preprocessedFingerprint(llvm::StringRef source, llvm::StringRef filename,
                                         llvm::ArrayRef<std::string> includePaths,
                                         llvm::ArrayRef<std::string> defines) {
  Diagnostics diags(filename, llvm::nulls());
  std::vector<Token> tokens;
  if (!lexAndPreprocess(source, diags, tokens, includePaths, defines))
    return "";
  std::string text;
  llvm::raw_string_ostream os(text);
  unsigned lastFile = ~0u;
  for (const Token &t : tokens) {
    if (t.loc.file != lastFile) {
      // File names are length-prefixed, so no name can imitate a token.
      llvm::StringRef name = diags.fileName(t.loc.file);
      os << "\nF" << name.size() << ":" << name;
      lastFile = t.loc.file;
    }
    os << "\n" << unsigned(t.kind) << " " << t.loc.line << ":" << t.loc.col << " "
       << t.text.size() << ":" << t.text;
  }
  return text;
}
