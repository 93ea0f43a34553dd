//===- LaneKernels.cpp - Choosing the instruction set's loops -------------===//
#include "LaneKernels.h"

#include "llvm/Support/raw_ostream.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>

namespace osl::render {

PrimTable::PrimTable(const Scene &scene) {
  for (const Primitive &p : scene.prims) {
    kind.push_back(p.kind);
    cx.push_back(p.center.x), cy.push_back(p.center.y), cz.push_back(p.center.z);
    radius.push_back(p.radius), r2.push_back(p.radius * p.radius);
    qx.push_back(p.corner.x), qy.push_back(p.corner.y), qz.push_back(p.corner.z);
    ex.push_back(p.edgeX.x), ey.push_back(p.edgeX.y), ez.push_back(p.edgeX.z);
    fx.push_back(p.edgeY.x), fy.push_back(p.edgeY.y), fz.push_back(p.edgeY.z);
    // A sphere's are never used: 1 keeps its lanes' quad math finite.
    QuadFrame f = p.kind == Primitive::Quad ? QuadFrame(p) : QuadFrame();
    nx.push_back(f.n.x), ny.push_back(f.n.y), nz.push_back(f.n.z);
    eu.push_back(f.eu), ev.push_back(f.ev);
    area.push_back(surfaceArea(p));
  }
}

void CosineMixtures::reset(size_t mixtures, int lobes) {
  mixtureCount = mixtures;
  maxCount = lobes;
  // Grown, never shrunk nor cleared: set() writes each mixture's own
  // slots, the kernels write the rest before reading them, and a slot past
  // a mixture's count is read only to be masked.
  // One row at least: a mixture without lobes reads (and ignores) row 0.
  size_t slots = mixtures * size_t(std::max(lobes, 1));
  growTo(slots, orenNayar, nx, ny, nz, sigma, wx, wy, wz, pick);
  growTo(mixtures, count, absorb, chosen, pwx, pwy, pwz, wox, woy, woz, rx, ry, wix, wiy, wiz,
         fx, fy, fz, pdf, roughness, total, accum);
}

void CosineMixtures::set(size_t m, const std::vector<Lobe> &lobes, Vec3 wo, Vec3 pathWeight,
                         bool mayEnd) {
  count[m] = int(lobes.size());
  for (size_t j = 0; j < lobes.size(); ++j) {
    const Lobe &l = lobes[j];
    size_t k = j * size() + m;
    Vec3 n = cosineLobeNormal(l);
    orenNayar[k] = l.model == Lobe::OrenNayar;
    nx[k] = n.x, ny[k] = n.y, nz[k] = n.z, sigma[k] = l.a;
    wx[k] = l.weight.x, wy[k] = l.weight.y, wz[k] = l.weight.z;
  }
  absorb[m] = mayEnd;
  pwx[m] = pathWeight.x, pwy[m] = pathWeight.y, pwz[m] = pathWeight.z;
  wox[m] = wo.x, woy[m] = wo.y, woz[m] = wo.z;
}

/// testrender's shapepdf: the sphere's cone, uniformly; the quad's area.
float lightPdf(const PrimTable &T, int k, Vec3 x, Vec3 p) {
  if (T.kind[k] == Primitive::Sphere) {
    Vec3 toC = Vec3(T.cx[k], T.cy[k], T.cz[k]) - x;
    float cmax2 = 1 - T.r2[k] / dot(toC, toC);
    float cmax = cmax2 > 0 ? std::sqrt(cmax2) : 0;
    return 1 / (float(2 * M_PI) * (1 - cmax));
  }
  Vec3 l = p - x;
  float d2 = dot(l, l);
  Vec3 dir = normalize(l);
  return d2 / (T.area[k] * std::fabs(dot(dir, Vec3(T.nx[k], T.ny[k], T.nz[k]))));
}

void HitPoints::sizeOutputs() {
  growTo(size(), ox, oy, oz, dx, dy, dz, px, py, pz, nx, ny, nz, dPdux, dPduy, dPduz, dPdvx, dPdvy,
         dPdvz, u, v, backfacing, area, dPdxX, dPdxY, dPdxZ, dPdyX, dPdyY, dPdyZ, dIdxX, dIdxY,
         dIdxZ, dIdyX, dIdyY, dIdyZ, dudx, dudy, dvdx, dvdy, flip, radius);
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
