//===- ArtisticIorBuiltin.cpp - artistic_ior ---------------------------------===//
//
// artistic_ior(reflectivity, edge_tint, output ior, output extinction): a
// conductor's complex index of refraction from two colors an artist picks,
// after Gulbrandsen, "Artist Friendly Metallic Fresnel", JCGT 3(4), 2014.
// MaterialX's conductor shaders call it before conductor_bsdf.
//
//===----------------------------------------------------------------------===//
#include "IRGen.h"

using namespace mlir;
using namespace mlir::osl;

namespace osl::frontend {

std::optional<RValue> emitArtisticIor(IRGen &g, const Expr &call) {
  if (call.args.size() != 4) {
    g.error(call.loc, "wrong arguments to 'artistic_ior'; candidates: void artistic_ior(color "
                      "reflectivity, color edge_tint, output color ior, output color "
                      "extinction)");
    return std::nullopt;
  }
  Value in[2];
  for (int k = 0; k < 2; ++k) {
    auto v = g.emitExpr(*call.args[k]);
    if (!v)
      return std::nullopt;
    auto c = g.coerce(*v, OslType(BaseType::Color), call.args[k]->loc,
                      "in argument " + llvm::Twine(k + 1) + " of 'artistic_ior'");
    if (!c)
      return std::nullopt;
    in[k] = c->value;
  }
  SrcLoc l = call.loc;
  OpBuilder &b = g.builder();
  Location ml = g.loc(l);
  auto splat = [&](float x) { return g.constTriple(x, x, x, l); };
  Value one = splat(1);
  // The reflectivity at normal incidence, kept below 1 (n would be infinite).
  Value r = b.create<ClampOp>(ml, in[0], splat(0), splat(0.99f));
  Value rootR = b.create<SqrtOp>(ml, r);
  // The edge tint picks n between the smallest index that reflects r with
  // no extinction and the largest (extinction 0 at the other end).
  Value nMin = b.create<DivOp>(ml, b.create<SubOp>(ml, one, r), b.create<AddOp>(ml, one, r));
  Value nMax =
      b.create<DivOp>(ml, b.create<AddOp>(ml, one, rootR), b.create<SubOp>(ml, one, rootR));
  Value n = b.create<MixOp>(ml, nMax, nMin, in[1]);
  // k^2 = (r (n+1)^2 - (n-1)^2) / (1 - r), which reproduces r at normal
  // incidence; rounding can make it slightly negative.
  Value nPlus = b.create<AddOp>(ml, n, one), nMinus = b.create<SubOp>(ml, n, one);
  Value k2 = b.create<DivOp>(ml,
                             b.create<SubOp>(ml, b.create<MulOp>(ml, b.create<MulOp>(ml, nPlus, nPlus), r),
                                             b.create<MulOp>(ml, nMinus, nMinus)),
                             b.create<SubOp>(ml, one, r));
  Value k = b.create<SqrtOp>(ml, b.create<MaxOp>(ml, k2, splat(0)));
  Value results[2] = {n, k};
  for (int j = 0; j < 2; ++j) {
    auto lv = g.emitLValue(*call.args[2 + j]);
    if (!lv)
      return std::nullopt;
    auto v = g.coerce(RValue::num(OslType(BaseType::Color), results[j]), lv->type,
                      call.args[2 + j]->loc,
                      "in output argument " + llvm::Twine(3 + j) + " of 'artistic_ior'");
    if (!v)
      return std::nullopt;
    g.storeLValue(*lv, *v, l);
  }
  return RValue::voidValue();
}

} // namespace osl::frontend
