//===- LaneKernels.cpp - Choosing the instruction set's loops -------------===//
#include "LaneKernels.h"

#include "llvm/Support/raw_ostream.h"

#include <cstdlib>
#include <cstring>

namespace osl::render {

void PointDraws::clear() {
  for (std::vector<uint32_t> *v : {&key, &index, &call})
    v->clear();
}

void PointDraws::push(uint32_t k, uint32_t i, uint32_t c) {
  key.push_back(k), index.push_back(i), call.push_back(c);
}

void CosineDraws::clear() {
  for (std::vector<float> *v : {&nx, &ny, &nz, &a, &rhoX, &rhoY, &rhoZ, &through, &weightX,
                                &weightY, &weightZ, &pick, &wox, &woy, &woz, &rx, &ry})
    v->clear();
}

void CosineDraws::push(const CosineLobe &l, Vec3 weight, float pickProbability, Vec3 wo,
                       float r0, float r1) {
  nx.push_back(l.n.x), ny.push_back(l.n.y), nz.push_back(l.n.z), a.push_back(l.a);
  rhoX.push_back(l.rho.x), rhoY.push_back(l.rho.y), rhoZ.push_back(l.rho.z);
  through.push_back(l.through ? 1.0f : 0.0f);
  weightX.push_back(weight.x), weightY.push_back(weight.y), weightZ.push_back(weight.z);
  pick.push_back(pickProbability);
  wox.push_back(wo.x), woy.push_back(wo.y), woz.push_back(wo.z);
  rx.push_back(r0), ry.push_back(r1);
}

BsdfSample CosineDraws::alone(size_t i) const {
  BsdfSample s;
  if (!(alonePdf[i] > 0))
    return s;
  s.wi = Vec3(wix[i], wiy[i], wiz[i]);
  s.value = Vec3(valueX[i], valueY[i], valueZ[i]);
  s.weight = Vec3(aloneX[i], aloneY[i], aloneZ[i]);
  s.pdf = alonePdf[i];
  s.diffuse = true; // every cosine lobe is
  return s;
}

PrimTable::PrimTable(const Scene &scene) {
  for (const Primitive &p : scene.prims) {
    kind.push_back(p.kind);
    cx.push_back(p.center.x), cy.push_back(p.center.y), cz.push_back(p.center.z);
    radius.push_back(p.radius);
    qx.push_back(p.corner.x), qy.push_back(p.corner.y), qz.push_back(p.corner.z);
    ex.push_back(p.edgeX.x), ey.push_back(p.edgeX.y), ez.push_back(p.edgeX.z);
    fx.push_back(p.edgeY.x), fy.push_back(p.edgeY.y), fz.push_back(p.edgeY.z);
    Vec3 n = p.kind == Primitive::Quad ? normalize(cross(p.edgeX, p.edgeY)) : Vec3();
    nx.push_back(n.x), ny.push_back(n.y), nz.push_back(n.z);
    // A sphere's never divide: 1 keeps its lanes' unused quad math finite.
    edgeX2.push_back(p.kind == Primitive::Quad ? dot(p.edgeX, p.edgeX) : 1.0f);
    edgeY2.push_back(p.kind == Primitive::Quad ? dot(p.edgeY, p.edgeY) : 1.0f);
    area.push_back(surfaceArea(p));
  }
}

float lightPdf(const PrimTable &T, int k, Vec3 x, Vec3 p) {
  if (T.kind[k] == Primitive::Sphere) {
    Vec3 toC = Vec3(T.cx[k], T.cy[k], T.cz[k]) - x;
    return sphereLightPdf(dot(toC, toC), T.radius[k] * T.radius[k]);
  }
  Vec3 d = p - x;
  float d2 = dot(d, d);
  return quadLightPdf(Vec3(T.nx[k], T.ny[k], T.nz[k]), T.area[k], d / std::sqrt(d2), d2);
}

void HitPoints::sizeOutputs() {
  for (std::vector<float> *v :
       {&ox, &oy,    &oz,    &dx,    &dy,    &dz,    &px,    &py, &pz, &nx,         &ny,
        &nz, &dPdux, &dPduy, &dPduz, &dPdvx, &dPdvy, &dPdvz, &u,  &v,  &backfacing, &area})
    v->resize(size());
}

namespace {

bool runsAvx512() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
         __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq");
}

bool runsAvx2() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2");
}

const LaneKernels &chooseLaneKernels() {
  if (const char *forced = std::getenv("OSL_MLIR_RENDER_ISA")) {
    if (!std::strcmp(forced, "generic"))
      return genericLaneKernels();
    if (!std::strcmp(forced, "avx2") && runsAvx2())
      return avx2LaneKernels();
    if (!std::strcmp(forced, "avx512") && runsAvx512())
      return avx512LaneKernels();
    llvm::errs() << "warning: OSL_MLIR_RENDER_ISA=" << forced
                 << " is not generic, avx2 or avx512 this CPU runs; choosing\n";
  }
  if (runsAvx512())
    return avx512LaneKernels();
  if (runsAvx2())
    return avx2LaneKernels();
  return genericLaneKernels();
}

} // namespace

std::vector<const LaneKernels *> laneKernelsThisCpuRuns() {
  std::vector<const LaneKernels *> all{&genericLaneKernels()};
  if (runsAvx2())
    all.push_back(&avx2LaneKernels());
  if (runsAvx512())
    all.push_back(&avx512LaneKernels());
  return all;
}

const LaneKernels &laneKernels() {
  static const LaneKernels &chosen = chooseLaneKernels();
  return chosen;
}

} // namespace osl::render
