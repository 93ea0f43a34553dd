//===- SincosBuiltin.cpp - sincos --------------------------------------------===//
//
// sincos(x, output s, output c): both from one call; fresnel, which also
// answers through output arguments, is built from the geometry emitters
// (Builtins.cpp).
//
//===----------------------------------------------------------------------===//
#include "IRGen.h"

#include "mlir/Dialect/Arith/IR/Arith.h"

using namespace mlir;
using namespace mlir::osl;

namespace osl::frontend {

/// sincos(x, output s, output c).
std::optional<RValue> emitSincos(IRGen &g, const Expr &call) {
  if (call.args.size() != 3) {
    g.error(call.loc, "wrong arguments to 'sincos'; candidates: void sincos(float, output "
                      "float, output float); void sincos(triple, output triple, output "
                      "triple)");
    return std::nullopt;
  }
  auto x = g.emitExpr(*call.args[0]);
  if (!x)
    return std::nullopt;
  if (x->type.isInt() || x->type.isBool())
    x = RValue::num(OslType(BaseType::Float),
                    g.convert(x->value, g.builder().getF32Type(), call.args[0]->loc));
  if (!x->type.isFloat() && !x->type.isTriple()) {
    g.error(call.args[0]->loc, "'sincos' needs a float or a triple, got '" +
                                   x->type.str() + "'");
    return std::nullopt;
  }
  Value s = g.builder().create<SinOp>(g.loc(call.loc), x->value);
  Value c = g.builder().create<CosOp>(g.loc(call.loc), x->value);
  for (int k = 1; k <= 2; ++k) {
    auto lv = g.emitLValue(*call.args[k]);
    if (!lv)
      return std::nullopt;
    auto v = g.coerce(RValue::num(x->type, k == 1 ? s : c), lv->type, call.args[k]->loc,
                      "in output argument " + llvm::Twine(k + 1) + " of 'sincos'");
    if (!v)
      return std::nullopt;
    g.storeLValue(*lv, *v, call.loc);
  }
  return RValue::voidValue();
}

} // namespace osl::frontend
