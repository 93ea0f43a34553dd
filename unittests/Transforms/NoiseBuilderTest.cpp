//===- NoiseBuilderTest.cpp - NoiseBuilder vs. osl::ref, JIT-executed -----===//
//
// Builds every noise variant with NoiseBuilder at widths 1 (f32), 4, 8 and
// 16, lowers to LLVM, JIT-compiles for the host and compares each lane with
// the scalar reference bit for bit. The reference itself is pinned to OSL's
// values by unittests/Reference/NoiseReferenceTest.cpp.
//
//===----------------------------------------------------------------------===//

#include "OslConversion/Passes.h"
#include "OslDialect/OslDialect.h"
#include "OslReference/Noise.h"
#include "OslLanes/NoiseBuilder.h"

#include "mlir/Dialect/Arith/IR/Arith.h"
#include "mlir/Dialect/Func/IR/FuncOps.h"
#include "mlir/Dialect/LLVMIR/LLVMDialect.h"
#include "mlir/Dialect/Math/IR/Math.h"
#include "mlir/ExecutionEngine/ExecutionEngine.h"
#include "mlir/ExecutionEngine/OptUtils.h"
#include "mlir/IR/Builders.h"
#include "mlir/IR/BuiltinOps.h"
#include "mlir/IR/Verifier.h"
#include "mlir/Pass/Pass.h"
#include "mlir/Pass/PassManager.h"
#include "mlir/Target/LLVMIR/Dialect/Builtin/BuiltinToLLVMIRTranslation.h"
#include "mlir/Target/LLVMIR/Dialect/LLVMIR/LLVMToLLVMIRTranslation.h"
#include "llvm/Support/TargetSelect.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

using namespace mlir;
namespace ref = ::osl::ref;
using mlir::osl::NoiseKind;

namespace {

struct Variant {
  NoiseKind kind;
  ref::NoiseType refType;
  int dims;
  bool triple;
  bool periodic;

  std::string name() const {
    static const char *names[] = {"perlin", "uperlin", "cell",
                                  "hash",   "simplex", "usimplex"};
    return std::string(periodic ? "periodic " : "") +
           names[static_cast<int>(refType)] + " " + std::to_string(dims) +
           "D " + (triple ? "triple" : "float");
  }
};

std::vector<Variant> allVariants() {
  const std::pair<NoiseKind, ref::NoiseType> kinds[] = {
      {NoiseKind::perlin, ref::NoiseType::Perlin},
      {NoiseKind::uperlin, ref::NoiseType::UPerlin},
      {NoiseKind::cell, ref::NoiseType::Cell},
      {NoiseKind::hash, ref::NoiseType::Hash},
      {NoiseKind::simplex, ref::NoiseType::Simplex},
      {NoiseKind::usimplex, ref::NoiseType::USimplex}};
  std::vector<Variant> out;
  for (auto [kind, refType] : kinds)
    for (int dims = 1; dims <= 4; ++dims)
      for (bool triple : {false, true})
        for (bool periodic : {false, true}) {
          bool simplex = refType == ref::NoiseType::Simplex ||
                         refType == ref::NoiseType::USimplex;
          if (!(periodic && simplex))
            out.push_back({kind, refType, dims, triple, periodic});
        }
  return out;
}

using Point = std::array<float, 4>;

/// Lattice points, fractions, ties (equal coordinates), huge, tiny, signed
/// zeros, out-of-int-range, inf and NaN, and random points at many scales.
std::vector<Point> testPoints() {
  std::vector<Point> pts = {
      {0, 0, 0, 0},           {1, 2, 3, 4},         {-1, -2, -3, -4},
      {0.5f, 0.5f, 0.5f, 0.5f}, {-0.5f, 1.5f, -2.5f, 3.5f},
      {0.999f, 1.001f, -0.999f, -1.001f}, {1e-6f, 2e-6f, -3e-6f, 4e-6f},
      {12345.678f, -2345.678f, 345.678f, -45.678f},
      {100000.25f, -99999.75f, 54321.5f, 0.5f}};
  const float special[] = {0.0f,   -0.0f,   1.0f,         -1.0f,
                           0.5f,   1e-30f,  16777216.5f,  3e9f,
                           -3e9f,  1e20f,   -1e38f,       2147483520.0f,
                           -2147483648.0f, INFINITY, -INFINITY, NAN};
  std::mt19937 rng(1234);
  for (int n = 0; n < 200; ++n) {
    Point p;
    for (float &c : p)
      c = special[rng() % (sizeof special / sizeof special[0])];
    pts.push_back(p);
  }
  for (int n = 0; n < 1000; ++n) {
    float span = std::pow(10.0f, static_cast<float>(rng() % 7) - 1.0f);
    std::uniform_real_distribution<float> u(-span, span);
    pts.push_back({u(rng), u(rng), u(rng), u(rng)});
  }
  for (int n = 0; n < 400; ++n) {
    std::uniform_real_distribution<float> u(-5.0f, 5.0f);
    float v[2] = {u(rng), u(rng)};
    pts.push_back({v[rng() & 1], v[rng() & 1], v[rng() & 1], v[rng() & 1]});
  }
  return pts;
}

const Point kPeriods[] = {{4, 3, 5, 2},
                          {1, 1, 1, 1},
                          {0, -2, 0.5f, 7.9f},
                          {2.5f, 1e6f, 3, 16},
                          {NAN, 3e9f, 256, 5}};

uint32_t bitsOf(float f) {
  uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

class NoiseBuilderTest : public ::testing::TestWithParam<int> {
protected:
  static void SetUpTestSuite() {
    llvm::InitializeNativeTarget();
    llvm::InitializeNativeTargetAsmPrinter();
  }
};

/// One function per variant: (coords*, periods*, out*), rows of W floats.
OwningOpRef<ModuleOp> buildModule(MLIRContext &ctx, int width,
                                  const std::vector<Variant> &variants) {
  OpBuilder b(&ctx);
  Location loc = b.getUnknownLoc();
  OwningOpRef<ModuleOp> module = ModuleOp::create(loc);
  b.setInsertionPointToEnd(module->getBody());
  Type f32 = b.getF32Type();
  Type lane = width == 1 ? f32 : Type(VectorType::get({width}, f32));
  auto ptr = LLVM::LLVMPointerType::get(&ctx);
  for (size_t v = 0; v < variants.size(); ++v) {
    const Variant &var = variants[v];
    auto fn = b.create<func::FuncOp>(loc, "variant" + std::to_string(v),
                                     b.getFunctionType({ptr, ptr, ptr}, {}));
    Block *entry = fn.addEntryBlock();
    OpBuilder fb = OpBuilder::atBlockBegin(entry);
    auto rowPtr = [&](Value base, int row) -> Value {
      Value idx = fb.create<LLVM::ConstantOp>(
          loc, fb.getI64Type(), fb.getI64IntegerAttr(int64_t(row) * width));
      return fb.create<LLVM::GEPOp>(loc, ptr, f32, base, ValueRange{idx});
    };
    SmallVector<Value> coords, periods;
    for (int a = 0; a < var.dims; ++a) {
      coords.push_back(fb.create<LLVM::LoadOp>(
          loc, lane, rowPtr(entry->getArgument(0), a), 4));
      periods.push_back(fb.create<LLVM::LoadOp>(
          loc, lane, rowPtr(entry->getArgument(1), a), 4));
    }
    SmallVector<Value, 3> results;
    if (var.triple) {
      std::array<Value, 3> t =
          var.periodic ? mlir::osl::buildPeriodicNoiseTriple(
                             fb, loc, var.kind, coords, periods)
                       : mlir::osl::buildNoiseTriple(fb, loc, var.kind, coords);
      results.assign(t.begin(), t.end());
    } else {
      results.push_back(var.periodic ? mlir::osl::buildPeriodicNoiseFloat(
                                           fb, loc, var.kind, coords, periods)
                                     : mlir::osl::buildNoiseFloat(
                                           fb, loc, var.kind, coords));
    }
    for (size_t r = 0; r < results.size(); ++r)
      fb.create<LLVM::StoreOp>(loc, results[r],
                               rowPtr(entry->getArgument(2), r), 4);
    fb.create<func::ReturnOp>(loc);
  }
  return module;
}

TEST_P(NoiseBuilderTest, BitExactWithReference) {
  const int width = GetParam();
  DialectRegistry registry;
  registry.insert<arith::ArithDialect, math::MathDialect, func::FuncDialect,
                  LLVM::LLVMDialect, mlir::osl::OslDialect>();
  registerBuiltinDialectTranslation(registry);
  registerLLVMDialectTranslation(registry);
  MLIRContext ctx(registry);
  ctx.loadAllAvailableDialects();

  std::vector<Variant> variants = allVariants();
  OwningOpRef<ModuleOp> module = buildModule(ctx, width, variants);
  ASSERT_TRUE(succeeded(verify(*module)));

  // Emitted ops must be arith and exact math ops only (besides the test's
  // own LLVM ops and the hash's codegen fences, which compute nothing):
  // floor and abs round nothing.
  module->walk([&](Operation *op) {
    if (isa<func::FuncOp, func::ReturnOp, ModuleOp, mlir::osl::CodegenFenceOp>(op) ||
        op->getDialect()->getNamespace() == "llvm")
      return;
    EXPECT_TRUE(isa<arith::ArithDialect>(op->getDialect()) ||
                (isa<math::FloorOp, math::AbsFOp>(op)))
        << "unexpected op " << op->getName().getStringRef().str();
    if (auto fm = op->getAttrOfType<arith::FastMathFlagsAttr>("fastmath"))
      EXPECT_EQ(fm.getValue(), arith::FastMathFlags::none);
  });

  // The kernels' own lowering (it lowers the fences too).
  PassManager pm(&ctx);
  pm.addPass(mlir::osl::createLowerToLLVM());
  ASSERT_TRUE(succeeded(pm.run(*module)));

  ExecutionEngineOptions options;
  options.transformer = makeOptimizingTransformer(/*optLevel=*/2,
                                                  /*sizeLevel=*/0, nullptr);
  auto engine = ExecutionEngine::create(*module, options);
  ASSERT_TRUE(bool(engine)) << llvm::toString(engine.takeError());

  std::vector<Point> pts = testPoints();
  std::vector<float> in(4 * width), per(4 * width), out(3 * width);
  for (size_t v = 0; v < variants.size(); ++v) {
    const Variant &var = variants[v];
    auto fn = (*engine)->lookupPacked("variant" + std::to_string(v));
    ASSERT_TRUE(bool(fn)) << var.name();
    int mismatches = 0;
    for (size_t first = 0; first < pts.size(); first += width) {
      for (int l = 0; l < width; ++l) {
        const Point &p = pts[(first + l) % pts.size()];
        const Point &pp = kPeriods[(first + l) % 5];
        for (int a = 0; a < 4; ++a) {
          in[a * width + l] = p[a];
          per[a * width + l] = pp[a];
        }
      }
      float *inPtr = in.data(), *perPtr = per.data(), *outPtr = out.data();
      void *args[] = {&inPtr, &perPtr, &outPtr};
      (*fn)(args);
      for (int l = 0; l < width; ++l) {
        float x[4], period[4], expected[3] = {0, 0, 0};
        for (int a = 0; a < 4; ++a) {
          x[a] = in[a * width + l];
          period[a] = per[a * width + l];
        }
        if (var.periodic) {
          if (var.triple)
            ref::periodicNoiseTriple(var.refType, var.dims, x, period,
                                     expected);
          else
            ref::periodicNoise(var.refType, var.dims, x, period, expected);
        } else if (var.triple) {
          ref::noiseTriple(var.refType, var.dims, x, expected);
        } else {
          expected[0] = ref::noise(var.refType, var.dims, x);
        }
        for (int c = 0; c < (var.triple ? 3 : 1); ++c) {
          float got = out[c * width + l];
          bool same = bitsOf(got) == bitsOf(expected[c]) ||
                      (std::isnan(got) && std::isnan(expected[c]));
          if (!same && ++mismatches <= 3)
            ADD_FAILURE() << var.name() << " width " << width << " channel "
                          << c << " at (" << x[0] << ", " << x[1] << ", "
                          << x[2] << ", " << x[3] << "): expected "
                          << expected[c] << ", got " << got;
        }
      }
    }
    EXPECT_EQ(mismatches, 0) << var.name() << " at width " << width;
  }
}

INSTANTIATE_TEST_SUITE_P(Widths, NoiseBuilderTest,
                         ::testing::Values(1, 4, 8, 16));

TEST(NoiseBuilderNames, FromOslNames) {
  using mlir::osl::noiseKindFromName;
  EXPECT_EQ(noiseKindFromName("perlin"), NoiseKind::perlin);
  EXPECT_EQ(noiseKindFromName("snoise"), NoiseKind::perlin);
  EXPECT_EQ(noiseKindFromName("uperlin"), NoiseKind::uperlin);
  EXPECT_EQ(noiseKindFromName("noise"), NoiseKind::uperlin);
  EXPECT_EQ(noiseKindFromName("cell"), NoiseKind::cell);
  EXPECT_EQ(noiseKindFromName("cellnoise"), NoiseKind::cell);
  EXPECT_EQ(noiseKindFromName("hash"), NoiseKind::hash);
  EXPECT_EQ(noiseKindFromName("hashnoise"), NoiseKind::hash);
  EXPECT_EQ(noiseKindFromName("simplex"), NoiseKind::simplex);
  EXPECT_EQ(noiseKindFromName("usimplex"), NoiseKind::usimplex);
  EXPECT_EQ(noiseKindFromName("gabor"), NoiseKind::gabor);
  EXPECT_FALSE(noiseKindFromName("pink").has_value());
  EXPECT_FALSE(noiseKindFromName("").has_value());
}

} // namespace
