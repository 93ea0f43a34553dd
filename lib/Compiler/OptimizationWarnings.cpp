//===- OptimizationWarnings.cpp - OSL's opt_warnings reports --------------===//
#include "OptimizationWarnings.h"

#include "OslDialect/OslDialect.h"

#include "llvm/ADT/StringSet.h"
#include "llvm/Support/raw_ostream.h"

using namespace mlir;

namespace osl {
namespace {

constexpr const char *kWarnLayerAttr = "osl.warn_layer";

bool isErrorCall(Operation *op) {
  auto print = dyn_cast<mlir::osl::PrintOp>(op);
  return print && print.isErrorCall();
}

bool mayWarn(Operation *op) {
  return isa<mlir::osl::StringCallOp, mlir::osl::TextureOp, mlir::osl::GetTextureInfoOp>(op) ||
         isErrorCall(op);
}

/// OSL's words for what `op` leaves to run time, or "" for nothing.
std::string issue(Operation *op, bool errorCalls) {
  if (isErrorCall(op))
    return errorCalls ? "error() call present in optimized shader." : "";
  if (auto call = dyn_cast<mlir::osl::StringCallOp>(op)) {
    llvm::StringRef callee = call.getCallee();
    if (callee == "concat" || callee == "format" || callee == "substr")
      return (callee + "(): new string creation couldn't be optimized to a constant.").str();
    return (callee + "(): need for string characters couldn't be optimized away.").str();
  }
  if (auto lookup = dyn_cast<mlir::osl::TextureOp>(op)) {
    if (!lookup.getFileHandle())
      return "";
    // The kinds are named after OSL's functions.
    return (mlir::osl::stringifyTextureKind(lookup.getKind()) +
            "(): texture name cannot be converted to a handle.")
        .str();
  }
  if (auto info = dyn_cast<mlir::osl::GetTextureInfoOp>(op))
    return info.getFileHandle() ? "gettextureinfo(): texture name cannot be converted to a handle."
                                : "";
  return "";
}

} // namespace

void tagLayerForWarnings(ModuleOp module, llvm::StringRef layerName) {
  Builder b(module.getContext());
  module.walk([&](Operation *op) {
    if (mayWarn(op))
      op->setAttr(kWarnLayerAttr, b.getStringAttr(layerName));
  });
}

std::string optimizationWarnings(ModuleOp module, llvm::StringRef groupName,
                                 bool errorCalls) {
  std::string text;
  llvm::raw_string_ostream os(text);
  llvm::StringSet<> reported; // lane groups clone a lookup: one report
  module.walk([&](Operation *op) {
    std::string what = mayWarn(op) ? issue(op, errorCalls) : "";
    if (what.empty())
      return;
    auto layer = op->getAttrOfType<StringAttr>(kWarnLayerAttr);
    std::string source;
    if (auto file = dyn_cast<FileLineColLoc>(op->getLoc()))
      source = (file.getFilename().getValue() + ":" + llvm::Twine(file.getLine())).str();
    std::string block = "WARNING: Optimization warning:\n  group:  " + groupName.str() +
                        "\n  layer:  " + (layer ? layer.getValue().str() : "") +
                        "\n  source: " + source + "\n  issue:  " + what + "\n";
    if (reported.insert(block).second)
      os << block;
  });
  return text;
}

} // namespace osl
