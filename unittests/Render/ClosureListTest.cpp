//===- ClosureListTest.cpp - Closures built in batches, read per lane -----===//
//
// A shader that builds its Ci under divergent control flow (if, loops,
// conditional sums) gives every lane the same flattened closure list,
// bit for bit, at widths 1, 4, 8 and 16; and the arena's sums and products
// flatten with their weights multiplied through.
//
//===----------------------------------------------------------------------===//
#include "OslCompiler/ShaderCompiler.h"
#include "OslRuntime/Closure.h"
#include "OslAbi/GlobalsLayout.h"
#include "OslRuntime/StringCall.h"

#include "llvm/Support/raw_ostream.h"

#include <gtest/gtest.h>

#include <cstring>
#include <vector>

using namespace osl;

namespace {

constexpr const char *kDivergentClosures = R"(
surface divergent(float Kd = 0.7)
{
    closure color c = 0;
    if (u > 0.5)
        c = Kd * diffuse(N);
    else if (v > 0.3)
        c = color(u, v, 0.25) * oren_nayar(N, v);
    for (int i = 0; i < (int)(u * 4); i++)
        c += 0.1 * i * microfacet("ggx", N, 0.1 + 0.1 * i, 1.5, i % 3);
    Ci = v > 0.8 ? c + emission() : c;
    if (u < 0.1)
        Ci = layer(0.5 * dielectric_bsdf(N, dPdu, color(1), color(0), u, v, 1.4, "beckmann",
                                         "label", "coat"), Ci);
}
)";

/// A flattened closure as comparable words: id, weight bits, parameter words.
using Flat = std::vector<uint32_t>;

void appendFlat(const ClosureArena &arena, int32_t handle, Flat &out) {
  std::vector<ClosurePrimitive> prims;
  arena.flatten(handle, prims);
  for (const ClosurePrimitive &p : prims) {
    out.push_back(uint32_t(p.id));
    for (float w : p.weight) {
      uint32_t bits;
      std::memcpy(&bits, &w, 4);
      out.push_back(bits);
    }
    char kinds[kMaxClosureParams];
    int32_t n = closureParamKinds(p.id, kinds, kMaxClosureParams);
    for (int32_t i = 0; i < n; ++i) {
      if (kinds[i] == 'k') { // a nested closure: its own list, not its handle
        appendFlat(arena, p.closureParam(i), out);
        continue;
      }
      if (kinds[i] == 's') { // handles are process-wide and stable; compare texts
        for (char ch : stringText(p.stringParam(i)))
          out.push_back(uint32_t(ch));
        continue;
      }
      for (int32_t w = 0; w < closureParamRows(kinds[i]); ++w)
        out.push_back(p.words[p.offset(i) + w]);
    }
    out.push_back(0xffffffffU); // end of primitive
  }
}

/// Each point's flattened Ci, shaded `points` at a time in batches of `width`.
std::vector<Flat> shadePoints(int width, int points) {
  CompileOptions options;
  options.width = width;
  std::string diagnostics;
  llvm::raw_string_ostream errs(diagnostics);
  ShaderCompiler compiler(options, errs);
  auto shader = compiler.compile(kDivergentClosures, "divergent.osl");
  EXPECT_TRUE(shader) << diagnostics;
  if (!shader)
    return {};
  int ciRow = -1, rows = 0;
  for (const OutputSpec &o : shader->outputs) {
    if (o.closure)
      ciRow = rows;
    rows += o.channels;
  }
  EXPECT_GE(ciRow, 0);
  std::vector<Flat> flats(points);
  std::vector<float> globals(size_t(kGlobalRows) * width), outputs(size_t(rows) * width);
  for (int first = 0; first < points; first += width) {
    int n = std::min(width, points - first);
    std::fill(globals.begin(), globals.end(), 0.0f);
    for (int lane = 0; lane < n; ++lane) {
      int i = first + lane;
      float u = float(i % 17) / 16, v = float(i / 17) / 16;
      globals[size_t(findGlobal("u")->row) * width + lane] = u;
      globals[size_t(findGlobal("v")->row) * width + lane] = v;
      globals[size_t(findGlobal("N")->row + 2) * width + lane] = 1;
      globals[size_t(findGlobal("dPdu")->row) * width + lane] = 1;
    }
    ClosureArena &arena = threadClosureArena();
    arena.reset();
    shader->kernel(globals.data(), outputs.data(), n);
    for (int lane = 0; lane < n; ++lane)
      appendFlat(arena, closureHandleFromOutput(outputs[size_t(ciRow) * width + lane]),
                 flats[first + lane]);
  }
  return flats;
}

TEST(ClosureListTest, DivergentClosuresAreBitIdenticalAtEveryWidth) {
  const int points = 17 * 17;
  std::vector<Flat> reference = shadePoints(1, points);
  ASSERT_EQ(int(reference.size()), points);
  // The shader's branches all happen: some points have 4+ primitives, some none.
  size_t longest = 0, empty = 0;
  for (const Flat &f : reference) {
    longest = std::max(longest, f.size());
    empty += f.empty();
  }
  EXPECT_GT(longest, 40u);
  EXPECT_GT(empty, 0u);
  for (int width : {4, 8, 16}) {
    std::vector<Flat> flats = shadePoints(width, points);
    ASSERT_EQ(flats.size(), reference.size());
    for (int i = 0; i < points; ++i)
      ASSERT_EQ(flats[i], reference[i]) << "point " << i << " at width " << width;
  }
}

TEST(ClosureListTest, ArenaFlattensWeightsThroughProductsAndSums) {
  ClosureArena arena;
  uint32_t normal[3];
  float up[3] = {0, 0, 1};
  std::memcpy(normal, up, 12);
  int32_t diffuse = arena.component(kDiffuse, normal, 3);
  int32_t emission = arena.component(kEmission, nullptr, 0);
  const float half[3] = {0.5f, 0.5f, 0.5f}, tint[3] = {1, 2, 4};
  int32_t sum = arena.add(arena.mul(diffuse, half), arena.mul(emission, tint));
  int32_t scaled = arena.mul(sum, tint);
  EXPECT_EQ(arena.add(0, scaled), scaled);
  EXPECT_EQ(arena.mul(0, tint), 0);
  std::vector<ClosurePrimitive> prims;
  arena.flatten(scaled, prims);
  ASSERT_EQ(prims.size(), 2u);
  EXPECT_EQ(prims[0].id, kDiffuse);
  EXPECT_EQ(prims[0].weight, (std::array<float, 3>{0.5f, 1, 2}));
  EXPECT_EQ(prims[0].tripleParam(0), (std::array<float, 3>{0, 0, 1}));
  EXPECT_EQ(prims[1].id, kEmission);
  EXPECT_EQ(prims[1].weight, (std::array<float, 3>{1, 4, 16}));
  // A handle that is not the arena's reads as empty rather than crashing.
  prims.clear();
  arena.flatten(12345, prims);
  EXPECT_TRUE(prims.empty());
  arena.reset();
  EXPECT_EQ(arena.nodeCount(), 0u);
}

// The kernels' batch calls make, lane by lane, the nodes one-lane calls
// make, skip the lanes outside the mask, and record which closures were
// made (readers skip passes on that).
TEST(ClosureListTest, ArenaBuildsLanesAsOneLaneCallsWould) {
  constexpr int32_t width = 4;
  // Lane l's normal is (l, 10 + l, 20 + l), as rows of `width` words.
  int32_t rows[3 * width];
  for (int32_t l = 0; l < width; ++l)
    for (int32_t c = 0; c < 3; ++c) {
      float f = float(10 * c + l);
      std::memcpy(&rows[c * width + l], &f, 4);
    }
  ClosureArena lanes, single;
  int32_t made[width];
  lanes.componentLanes(kDiffuse, rows, 3, width, 0b1011, made);
  EXPECT_EQ(made[2], 0);
  float weights[3 * width];
  for (int32_t i = 0; i < 3 * width; ++i)
    weights[i] = float(i % 5); // lane 0's weight is (0, 4, 3); lane 3's (3, 2, 1)
  weights[0] = weights[width] = weights[2 * width] = 0; // lane 0: a zero weight, no node
  int32_t scaled[width];
  lanes.mulLanes(made, weights, width, 0b1111, scaled);
  EXPECT_EQ(scaled[0], 0);
  EXPECT_EQ(scaled[2], 0); // lane 2 had no closure
  // A lane outside the mask makes no product, whatever its operands.
  int32_t masked[width];
  size_t nodes = lanes.nodeCount();
  lanes.mulLanes(made, weights, width, 0b0101, masked);
  EXPECT_EQ(masked[1], 0);
  EXPECT_EQ(masked[3], 0);
  EXPECT_EQ(lanes.nodeCount(), nodes);
  EXPECT_TRUE(lanes.madeAny(ClosureArena::idBit(kDiffuse)));
  EXPECT_FALSE(lanes.madeAny(ClosureArena::idBit(kMxDielectric) | ClosureArena::idBit(kMxLayer)));
  for (int32_t l : {1, 3}) {
    uint32_t normal[3];
    for (int32_t c = 0; c < 3; ++c)
      normal[c] = uint32_t(rows[c * width + l]);
    const float w[3] = {weights[l], weights[width + l], weights[2 * width + l]};
    int32_t one = single.mul(single.component(kDiffuse, normal, 3), w);
    std::vector<ClosurePrimitive> got, want;
    lanes.flatten(scaled[l], got);
    single.flatten(one, want);
    ASSERT_EQ(got.size(), 1u) << "lane " << l;
    EXPECT_EQ(got[0].id, want[0].id);
    EXPECT_EQ(got[0].weight, want[0].weight) << "lane " << l;
    EXPECT_EQ(got[0].tripleParam(0), want[0].tripleParam(0)) << "lane " << l;
    EXPECT_EQ(got[0].tripleParam(0), (std::array<float, 3>{float(l), float(10 + l), float(20 + l)}));
  }
  // Lanes 0, 1 and 3 each made a component; lanes 1 and 3 a product.
  EXPECT_EQ(nodes, 5u);
  lanes.reset();
  EXPECT_FALSE(lanes.madeAny(ClosureArena::idBit(kDiffuse)));
}

} // namespace
