//===- MathKernel.cpp - one library math function as an array kernel -----===//
//
// The kernel is a loop over the arrays in lane-sized steps whose body is
// the function's lane builder (LaneMath.h), so it measures exactly what a
// shader's call computes, edge rules included. Width 1 uses scalars, as a
// uniform value in a shader does.
//
//===----------------------------------------------------------------------===//
#include "OslCompiler/MathKernel.h"
#include "OslDialect/OslDialect.h"

#include "OslLanes/LaneMath.h"
#include "OslLanes/NoiseBuilder.h"
#include "OslConversion/Passes.h"
#include "OslTransforms/Passes.h"

#include "mlir/IR/Builders.h"
#include "mlir/IR/BuiltinOps.h"
#include "mlir/Pass/PassManager.h"
#include "mlir/Target/LLVMIR/Dialect/Builtin/BuiltinToLLVMIRTranslation.h"
#include "mlir/Target/LLVMIR/Dialect/LLVMIR/LLVMToLLVMIRTranslation.h"
#include "mlir/Target/LLVMIR/Export.h"
#include "mlir/Transforms/Passes.h"
#include "llvm/ADT/TypeSwitch.h"
#include "llvm/IR/Constants.h"
#include "llvm/IR/Instructions.h"
#include "llvm/IR/LLVMContext.h"
#include "llvm/IR/Metadata.h"
#include "llvm/IR/Module.h"

#include <cfloat>
#include <cmath>
#include <random>

using namespace mlir;
using namespace ::osl::math;
namespace lane = ::mlir::osl::lane;
using ::osl::math::Function;

namespace {
using LaneFn = Value (*)(OpBuilder &, Location, ValueRange);

struct Entry {
  Function f;
  LaneFn build;
};

Value perlin2(OpBuilder &b, Location loc, ValueRange x) {
  return mlir::osl::buildNoiseFloat(b, loc, mlir::osl::NoiseKind::perlin, x);
}
Value simplex2(OpBuilder &b, Location loc, ValueRange x) {
  return mlir::osl::buildNoiseFloat(b, loc, mlir::osl::NoiseKind::simplex, x);
}
Value cell2(OpBuilder &b, Location loc, ValueRange x) {
  return mlir::osl::buildNoiseFloat(b, loc, mlir::osl::NoiseKind::cell, x);
}

/// No bound: MLIR's tan (sin/cos) gives +-inf and NaN at large arguments.
constexpr double kNoBound = INFINITY;

// Bounds: the largest error each implementation showed on the sweep of
// bench/osl-mathbench (2^17 points, bench/MATH.md) times 1.25, rounded up
// to two digits. One criterion each: ULPs where the relative error is
// meaningful, else absolute error (0 = not used); at precise, ulp counts
// floats from the correctly rounded result. The stability tests hold every
// implementation to them.
const std::vector<Entry> &entries() {
  static const std::vector<Entry> table = {
      // name, arity, lo, hi, magLo, ulp{fast, default, precise, polynomial}, abs{...}
      {{"sin", 1, -1e5, 1e5, 1e-6, {0, 0, 1, 0}, {0.0083, 1.3e-06, 0, 0.0083}}, lane::sin},
      {{"cos", 1, -1e5, 1e5, 1e-6, {0, 0, 1, 0}, {1.3, 1.7e-06, 0, 1.3}}, lane::cos},
      {{"tan", 1, -1e5, 1e5, 1e-6, {0, 0, 1, kNoBound}, {200, 200, 0, 0}}, lane::tan},
      {{"asin", 1, -1, 1, 1e-6, {0, 0, 1, 51}, {1.2e-05, 5.7e-05, 0, 0}}, lane::asin},
      {{"acos", 1, -1, 1, 1e-6, {400, 0, 1, 51}, {0, 5.7e-05, 0, 0}}, lane::acos},
      {{"atan", 1, -1e6, 1e6, 1e-6, {0, 0, 1, 50}, {1.2e-05, 1.2e-05, 0, 0}}, lane::atan},
      {{"atan2", 2, -100, 100, 1e-4, {0, 0, 1, 51}, {1.2e-05, 1.2e-05, 0, 0}}, lane::atan2},
      {{"sinh", 1, -87.3, 87.3, 1e-6, {13, 360, 1, 13}, {0, 7.5e-08, 0, 0}}, lane::sinh},
      {{"cosh", 1, -87.3, 87.3, 1e-6, {2.3, 320, 1, 2.3}, {0, 0, 0, 0}}, lane::cosh},
      {{"tanh", 1, -9, 9, 1e-6, {5.7, 0, 1, 5.7}, {0, 3.8e-06, 0, 0}}, lane::tanh},
      {{"exp", 1, -87.3, 87.3, 1e-6, {1.2, 220, 1, 1.2}, {0, 0, 0, 0}}, lane::exp},
      {{"exp2", 1, -126, 126, 1e-6, {85, 150, 1, 85}, {0, 0, 0, 0}}, lane::exp2},
      {{"expm1", 1, -87.3, 87.3, 1e-6, {3, 360, 1, 3}, {0, 5.7e-06, 0, 0}}, lane::expm1},
      {{"log", 1, FLT_MIN, FLT_MAX, FLT_MIN, {1, 0, 1, 1}, {0, 8.5e-06, 0, 0}}, lane::log},
      {{"log2", 1, FLT_MIN, FLT_MAX, FLT_MIN, {1.7, 0, 1, 1.7}, {0, 5e-06, 0, 0}}, lane::log2},
      {{"log10", 1, FLT_MIN, FLT_MAX, FLT_MIN, {2.6, 0, 1, 2.6}, {0, 7e-06, 0, 0}}, lane::log10},
      {{"pow", 2, -16, 16, 1e-3, {240, 240, 1, 160}, {0, 0, 0, 0}}, lane::pow},
      {{"erf", 1, -4, 4, 1e-6, {5.2, 0, 1, 5.2}, {0, 2.3e-06, 0, 0}}, lane::erf},
      {{"erfc", 1, -4, 4, 1e-6, {0, 0, 1, 0}, {3.3e-07, 2.4e-06, 0, 3.3e-07}}, lane::erfc},
      {{"cbrt", 1, -1e30, 1e30, 1e-30, {15, 16, 1, 15}, {0, 0, 0, 0}}, lane::cbrt},
      {{"sqrt", 1, 0, FLT_MAX, FLT_MIN, {0.5, 0.5, 1, 0.5}, {0, 0, 0, 0}}, lane::sqrt},
      {{"inversesqrt", 1, FLT_MIN, FLT_MAX, FLT_MIN, {1.9, 1.9, 1, 1.9}, {0, 0, 0, 0}},
       lane::inverseSqrt},
      // Noise (x, y): the error of its float arithmetic.
      {{"perlin", 2, -1000, 1000, 1e-3, {0, 0, 0, 0}, {3e-6, 3e-6, 3e-6, 3e-6}, true},
       perlin2},
      {{"simplex", 2, -1000, 1000, 1e-3, {0, 0, 0, 0}, {4.6e-4, 4.6e-4, 4.6e-4, 4.6e-4}, true},
       simplex2},
      {{"cellnoise", 2, -1000, 1000, 1e-3, {0.5, 0.5, 1, 0.5}, {0, 0, 0, 0}, true}, cell2},
  };
  return table;
}

const Entry *findEntry(const std::string &name) {
  for (const Entry &e : entries())
    if (name == e.f.name)
      return &e;
  return nullptr;
}

/// glibc's name for `op` at `width` (x86-64 vector ABI: b = SSE 4 lanes,
/// d = AVX2 8, e = AVX-512 16), or "" for an op it does not replace.
std::string libmvecName(Operation *op, int width) {
  const char *base = llvm::TypeSwitch<Operation *, const char *>(op)
                         .Case<mlir::math::SinOp>([](auto) { return "sinf"; })
                         .Case<mlir::math::CosOp>([](auto) { return "cosf"; })
                         .Case<mlir::math::TanOp>([](auto) { return "tanf"; })
                         .Case<mlir::math::AtanOp>([](auto) { return "atanf"; })
                         .Case<mlir::math::Atan2Op>([](auto) { return "atan2f"; })
                         .Case<mlir::math::ExpOp>([](auto) { return "expf"; })
                         .Case<mlir::math::Exp2Op>([](auto) { return "exp2f"; })
                         .Case<mlir::math::ExpM1Op>([](auto) { return "expm1f"; })
                         .Case<mlir::math::LogOp>([](auto) { return "logf"; })
                         .Case<mlir::math::Log2Op>([](auto) { return "log2f"; })
                         .Case<mlir::math::Log10Op>([](auto) { return "log10f"; })
                         .Case<mlir::math::PowFOp>([](auto) { return "powf"; })
                         .Case<mlir::math::TanhOp>([](auto) { return "tanhf"; })
                         .Case<mlir::math::ErfOp>([](auto) { return "erff"; })
                         .Default([](Operation *) { return nullptr; });
  if (!base)
    return "";
  if (width == 1)
    return base;
  const char *isa = width == 4 ? "b" : width == 8 ? "d" : "e";
  std::string args(op->getNumOperands(), 'v');
  return std::string("_ZGV") + isa + "N" + std::to_string(width) + args + "_" + base;
}

/// Replaces the math ops libmvec has by calls to it.
void callLibmvec(ModuleOp module, int width) {
  SmallVector<Operation *> ops;
  module.walk([&](Operation *op) {
    if (isa<mlir::math::MathDialect>(op->getDialect()) && !libmvecName(op, width).empty())
      ops.push_back(op);
  });
  OpBuilder b(module.getContext());
  for (Operation *op : ops) {
    std::string name = libmvecName(op, width);
    auto type = b.getFunctionType(op->getOperandTypes(), op->getResultTypes());
    if (!module.lookupSymbol(name)) {
      b.setInsertionPointToStart(module.getBody());
      b.create<func::FuncOp>(op->getLoc(), name, type).setPrivate();
    }
    b.setInsertionPoint(op);
    auto call = b.create<func::CallOp>(op->getLoc(), name, op->getResultTypes(),
                                       op->getOperands());
    op->getResult(0).replaceAllUsesWith(call.getResult(0));
    op->erase();
  }
}

/// `f64`: the function is built on f64 values and stores doubles;
/// `storeDouble`: built on f32 values, the result extended to f64 and stored
/// as a double (osl-evaluate-in-double then removes every rounding).
OwningOpRef<ModuleOp> buildModule(MLIRContext &ctx, LaneFn build, int arity, int width,
                                  bool f64, bool storeDouble) {
  OpBuilder b(&ctx);
  Location loc = b.getUnknownLoc();
  OwningOpRef<ModuleOp> module = ModuleOp::create(loc);
  b.setInsertionPointToEnd(module->getBody());
  auto ptr = LLVM::LLVMPointerType::get(&ctx);
  Type f32 = b.getF32Type(), outElement = f64 || storeDouble ? b.getF64Type() : f32;
  auto laneOf = [&](Type element) -> Type {
    return width == 1 ? element : VectorType::get({width}, element);
  };
  auto fn = b.create<func::FuncOp>(loc, "kernel",
                                   b.getFunctionType({ptr, ptr, ptr, b.getI64Type()}, {}));
  Block *entry = fn.addEntryBlock();
  b.setInsertionPointToStart(entry);
  Value zero = b.create<arith::ConstantIntOp>(loc, 0, 64);
  Value step = b.create<arith::ConstantIntOp>(loc, width, 64);
  auto loop = b.create<scf::ForOp>(loc, zero, entry->getArgument(3), step);
  b.setInsertionPointToStart(loop.getBody());
  Value i = loop.getInductionVar();
  SmallVector<Value, 2> args;
  for (int a = 0; a < arity; ++a) {
    Value p = b.create<LLVM::GEPOp>(loc, ptr, f32, entry->getArgument(a), ValueRange{i});
    Value v = b.create<LLVM::LoadOp>(loc, laneOf(f32), p, 4);
    if (f64)
      v = b.create<arith::ExtFOp>(loc, laneOf(outElement), v);
    args.push_back(v);
  }
  Value r = build(b, loc, args);
  if (storeDouble)
    r = b.create<arith::ExtFOp>(loc, laneOf(outElement), r);
  Value p = b.create<LLVM::GEPOp>(loc, ptr, outElement, entry->getArgument(2), ValueRange{i});
  b.create<LLVM::StoreOp>(loc, r, p, 4);
  b.setInsertionPointToEnd(entry);
  b.create<func::ReturnOp>(loc);
  return module;
}

/// The loop must run the kernel as a shader runs it: one step of `width`
/// points at a time. LLVM's loop vectorizer would otherwise widen the
/// width-1 loop to 16 lanes (and unrolling would let SLP do the same),
/// measuring a width that the shader never runs at.
void keepOneStepPerIteration(llvm::Module &ir) {
  llvm::LLVMContext &c = ir.getContext();
  auto flag = [&](const char *name, llvm::Constant *value) -> llvm::Metadata * {
    llvm::Metadata *ops[] = {llvm::MDString::get(c, name), llvm::ConstantAsMetadata::get(value)};
    return llvm::MDNode::get(c, ops);
  };
  for (llvm::Function &fn : ir)
    for (llvm::BasicBlock &bb : fn)
      if (auto *br = llvm::dyn_cast<llvm::BranchInst>(bb.getTerminator())) {
        llvm::Metadata *ops[] = {
            nullptr,
            flag("llvm.loop.vectorize.enable", llvm::ConstantInt::getFalse(c)),
            flag("llvm.loop.interleave.count", llvm::ConstantInt::get(llvm::Type::getInt32Ty(c), 1)),
            llvm::MDNode::get(c, {llvm::MDString::get(c, "llvm.loop.unroll.disable")})};
        llvm::MDNode *loop = llvm::MDNode::getDistinct(c, ops);
        loop->replaceOperandWith(0, loop);
        br->setMetadata(llvm::LLVMContext::MD_loop, loop);
      }
}

} // namespace

const char *::osl::math::implName(Impl impl) {
  switch (impl) {
  case Impl::Fast:
    return "fast";
  case Impl::Default:
    return "default";
  case Impl::Precise:
    return "precise";
  case Impl::Polynomial:
    return "polynomial";
  case Impl::Libmvec:
    return "libmvec";
  case Impl::Reference:
    return "reference";
  }
  return "?";
}

const std::vector<Function> &::osl::math::functions() {
  static const std::vector<Function> list = [] {
    std::vector<Function> out;
    for (const Entry &e : entries())
      out.push_back(e.f);
    return out;
  }();
  return list;
}

const Function *::osl::math::findFunction(const std::string &name) {
  const Entry *e = findEntry(name);
  return e ? &e->f : nullptr;
}

void ::osl::math::sampleDomain(const Function &f, size_t n, std::vector<float> &x,
                             std::vector<float> &y) {
  std::mt19937_64 rng(0x5eed + f.arity);
  std::uniform_real_distribution<double> unit(0, 1);
  double top = std::max(std::fabs(f.lo), std::fabs(f.hi));
  auto one = [&](size_t i) {
    double t = (double(i) + unit(rng)) / double(n); // stratified
    if (i % 2 == 0 || f.magLo <= 0)
      return float(f.lo + (f.hi - f.lo) * t);
    double mag = std::exp(std::log(f.magLo) + (std::log(top) - std::log(f.magLo)) * t);
    bool negative = f.lo < 0 && (f.hi <= 0 || (rng() & 1));
    double v = negative ? -mag : mag;
    return float(std::min(std::max(v, f.lo), f.hi));
  };
  x.resize(n);
  for (size_t i = 0; i < n; ++i)
    x[i] = one(i);
  y.assign(n, 0.0f);
  if (f.arity == 2) {
    for (size_t i = 0; i < n; ++i)
      y[i] = one(i);
    std::shuffle(y.begin(), y.end(), rng); // pair every x with every scale of y
  }
}

void ::osl::math::edgeInputs(const Function &f, std::vector<float> &x, std::vector<float> &y) {
  const float values[] = {0.0f,     -0.0f,     1e-45f,    -1e-45f,  1e-40f,  -1e-40f,
                          FLT_MIN,  -FLT_MIN,  1e-30f,    0.5f,     1.0f,    -1.0f,
                          2.0f,     -2.0f,     3.0f,      -3.0f,    0.5f,    -0.5f,
                          100.0f,   -100.0f,   88.8f,     -88.8f,   127.5f,  -150.0f,
                          1e5f,     -1e5f,     8388609.0f, 1e10f,   -1e10f,  1e30f,
                          -1e30f,   FLT_MAX,   -FLT_MAX,  INFINITY, -INFINITY, NAN};
  x.clear();
  y.clear();
  for (float a : values) {
    if (f.arity == 1) {
      x.push_back(a);
      y.push_back(0.0f);
      continue;
    }
    for (float c : values) {
      x.push_back(a);
      y.push_back(c);
    }
  }
}

double ::osl::math::ulpError(float result, double reference) {
  if (std::isnan(reference) || std::isnan(result))
    return std::isnan(reference) && std::isnan(result) ? 0 : INFINITY;
  if (std::isinf(reference) || std::isinf(result))
    return double(result) == reference ? 0 : INFINITY;
  float rounded = float(reference);
  double ulp = std::ldexp(1.0, -149);
  if (std::fabs(rounded) >= FLT_MIN) {
    int e;
    std::frexp(double(rounded), &e); // |rounded| = m 2^e, m in [0.5, 1)
    ulp = std::ldexp(1.0, e - 24);
  }
  return std::fabs(double(result) - reference) / ulp;
}

llvm::Expected<std::unique_ptr<Kernel>> Kernel::compile(const Function &f, Impl impl,
                                                        int width) {
  const Entry *e = findEntry(f.name);
  if (!e)
    return llvm::createStringError("unknown function '%s'", f.name);
  DialectRegistry registry;
  // The osl dialect for the noise hashes' codegen fences.
  registry.insert<func::FuncDialect, arith::ArithDialect, mlir::math::MathDialect,
                  scf::SCFDialect, vector::VectorDialect, cf::ControlFlowDialect,
                  LLVM::LLVMDialect, mlir::osl::OslDialect>();
  registerBuiltinDialectTranslation(registry);
  registerLLVMDialectTranslation(registry);
  MLIRContext ctx(registry, MLIRContext::Threading::DISABLED);
  ctx.loadAllAvailableDialects();
  bool reference = impl == Impl::Reference;
  OwningOpRef<ModuleOp> module = buildModule(ctx, e->build, f.arity, width,
                                             reference && !f.noise, reference && f.noise);
  if (impl == Impl::Libmvec)
    callLibmvec(*module, width);

  PassManager pm(&ctx);
  mlir::osl::ApproximateMathOptions options;
  options.level = impl == Impl::Fast         ? mlir::osl::MathLevel::Fast
                  : impl == Impl::Polynomial ? mlir::osl::MathLevel::Polynomial
                  : impl == Impl::Precise || impl == Impl::Reference
                      ? mlir::osl::MathLevel::Precise
                      : mlir::osl::MathLevel::Default;
  pm.addPass(mlir::osl::createApproximateMath(options));
  if (reference && f.noise)
    pm.addPass(mlir::osl::createEvaluateInDouble());
  pm.addPass(createCanonicalizerPass());
  pm.addPass(createCSEPass());
  pm.addPass(mlir::osl::createLowerToLLVM());
  if (failed(pm.run(*module)))
    return llvm::createStringError("lowering %s (%s) failed", f.name, implName(impl));

  auto llvmContext = std::make_unique<llvm::LLVMContext>();
  std::unique_ptr<llvm::Module> ir = translateModuleToLLVMIR(*module, *llvmContext, f.name);
  if (!ir)
    return llvm::createStringError("translating %s to LLVM IR failed", f.name);
  keepOneStepPerIteration(*ir);
  auto jit = ::osl::Jit::create();
  if (!jit)
    return jit.takeError();
  if (llvm::Error err = (*jit)->optimize(*ir))
    return std::move(err);
  if (llvm::Error err = (*jit)->addModule(std::move(ir), std::move(llvmContext)))
    return std::move(err);
  auto symbol = (*jit)->lookup("kernel");
  if (!symbol)
    return symbol.takeError();
  auto kernel = std::unique_ptr<Kernel>(new Kernel());
  kernel->fn = reinterpret_cast<Fn>(*symbol);
  kernel->w = width;
  kernel->jit = std::move(*jit);
  return kernel;
}

namespace {
/// Runs `kernel` on inputs padded with 1s to a whole number of batches and
/// keeps the first x.size() results (f32 kernels, or f64 for the double
/// reference).
template <typename Result>
void runOnWholeBatches(const Kernel &kernel, const std::vector<float> &x,
                       const std::vector<float> &y, std::vector<Result> &out) {
  size_t n = x.size(), w = size_t(kernel.width()), padded = (n + w - 1) / w * w;
  std::vector<float> px(x), py(y);
  px.resize(padded, 1.0f);
  py.resize(padded, 1.0f);
  out.assign(padded, Result(0));
  kernel.run(px.data(), py.data(), out.data(), int64_t(padded));
  out.resize(n);
}
} // namespace

void Kernel::runPadded(const std::vector<float> &x, const std::vector<float> &y,
                       std::vector<float> &out) const {
  runOnWholeBatches(*this, x, y, out);
}

void Kernel::runReference(const std::vector<float> &x, const std::vector<float> &y,
                          std::vector<double> &out) const {
  runOnWholeBatches(*this, x, y, out);
}
