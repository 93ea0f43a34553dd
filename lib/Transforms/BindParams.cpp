//===- BindParams.cpp - Instance values for shader parameters -------------===//
//
// Binding values at JIT time turns parameters into constants, which the
// canonicalizer then folds through the shader (OSL's render-time
// specialisation in its simplest form).
//
//===----------------------------------------------------------------------===//
#include "OslDialect/OslDialect.h"
#include "OslTransforms/Passes.h"

#include "mlir/IR/Builders.h"
#include "llvm/ADT/StringMap.h"
#include "llvm/ADT/StringSet.h"

namespace mlir::osl {
#define GEN_PASS_DEF_BINDPARAMS
#include "OslTransforms/Passes.h.inc"
} // namespace mlir::osl

using namespace mlir;
using namespace mlir::osl;

namespace {

/// "a=1;b=0.1,0.2,0.3" -> {a: [1], b: [0.1, 0.2, 0.3]}.
FailureOr<llvm::StringMap<SmallVector<double>>> parseValues(StringRef text,
                                                           std::string &error) {
  llvm::StringMap<SmallVector<double>> values;
  SmallVector<StringRef> entries;
  text.split(entries, ';', -1, /*KeepEmpty=*/false);
  for (StringRef entry : entries) {
    auto [name, list] = entry.split('=');
    name = name.trim();
    SmallVector<StringRef> numbers;
    list.split(numbers, ',', -1, false);
    if (name.empty() || numbers.empty()) {
      error = ("malformed parameter binding '" + entry + "'").str();
      return failure();
    }
    for (StringRef n : numbers) {
      double d;
      if (n.trim().getAsDouble(d)) {
        error = ("parameter '" + name + "': '" + n.trim() + "' is not a number").str();
        return failure();
      }
      values[name].push_back(d);
    }
  }
  return values;
}

Value buildConstant(OpBuilder &b, Location loc, Type type, ArrayRef<double> v) {
  Type base = getUniformType(type);
  Value c;
  if (base.isF32())
    c = b.create<arith::ConstantOp>(loc, b.getF32FloatAttr(v[0]));
  else if (base.isInteger(32))
    c = b.create<arith::ConstantOp>(loc, b.getI32IntegerAttr(int32_t(v[0])));
  else {
    SmallVector<float> xyz = {float(v[0]), float(v[v.size() > 1 ? 1 : 0]),
                              float(v[v.size() > 2 ? 2 : 0])};
    c = b.create<arith::ConstantOp>(
        loc, DenseElementsAttr::get(cast<ShapedType>(base), ArrayRef<float>(xyz)));
  }
  if (isVarying(type))
    c = b.create<BroadcastOp>(loc, type, c);
  return c;
}

struct BindParamsPass : public mlir::osl::impl::BindParamsBase<BindParamsPass> {
  using mlir::osl::impl::BindParamsBase<BindParamsPass>::BindParamsBase;

  void runOnOperation() override {
    std::string error;
    auto parsed = parseValues(values, error);
    if (failed(parsed)) {
      getOperation().emitError(error);
      return signalPassFailure();
    }
    llvm::StringMap<SmallVector<double>> &bindings = *parsed;
    llvm::StringSet<> seen;
    bool failedBinding = false;
    getOperation().walk([&](ParamOp param) {
      seen.insert(param.getName());
      Value replacement = param.getDefaultValue();
      auto it = bindings.find(param.getName());
      if (it != bindings.end()) {
        Type base = getUniformType(param.getType());
        size_t want = isTriple(base) ? 3 : 1;
        if (it->second.size() != want && !(want == 3 && it->second.size() == 1)) {
          param.emitError("parameter '") << param.getName() << "' takes "
                                         << want << " value(s)";
          failedBinding = true;
          return;
        }
        OpBuilder b(param);
        replacement = buildConstant(b, param.getLoc(), param.getType(), it->second);
      }
      param.replaceAllUsesWith(replacement);
      param.erase();
    });
    for (auto &entry : bindings)
      if (!seen.contains(entry.getKey())) {
        getOperation().emitError("shader has no parameter '")
            << entry.getKey() << "'";
        failedBinding = true;
      }
    if (failedBinding)
      signalPassFailure();
  }
};

} // namespace
