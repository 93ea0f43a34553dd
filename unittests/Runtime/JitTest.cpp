//===- JitTest.cpp - Optimize, JIT and run a batch kernel ------------------===//
//
// The kernels are LLVM IR text in the shape the compiler emits: vectors of
// W floats read from the globals rows and masked stores to the output rows.
//
//===----------------------------------------------------------------------===//

#include "OslRuntime/Grid.h"
#include "OslRuntime/Jit.h"
#include "OslRuntime/Stats.h"

#include "llvm/AsmParser/Parser.h"
#include "llvm/IR/IRBuilder.h"
#include "llvm/IR/LLVMContext.h"
#include "llvm/IR/Module.h"
#include "llvm/Support/SourceMgr.h"
#include "llvm/Support/raw_ostream.h"
#include "llvm/Target/TargetMachine.h"

#include "gtest/gtest.h"

#include <cmath>
#include <string>

using namespace osl;

// Found by the JIT through the process symbol table (the test executable
// is linked with ENABLE_EXPORTS).
extern "C" float osl_test_exported_scale(float x) { return 2.0f * x; }

namespace {

// Reached only through Jit::defineSymbols: not exported.
float hiddenOffset(float x) { return x + 0.25f; }

/// "<W x i32> <i32 0, i32 1, ...>"
std::string laneIndices(int w) {
  std::string s = "<" + std::to_string(w) + " x i32> <";
  for (int i = 0; i < w; ++i)
    s += (i ? ", i32 " : "i32 ") + std::to_string(i);
  return s + ">";
}

/// A width-W kernel with the GlobalsLayout ABI and three output channels:
///   out0 = u * v
///   out1 = sqrt(P.x) * osl_test_exported_scale(1.5)   (= 3 * sqrt(u))
///   out2 = hidden(v)                                   (= v + 0.25, per lane)
/// Stores are masked by lane < nactive, as the ABI requires.
std::string kernelIR(int w, const std::string &name) {
  std::string W = std::to_string(w), vf = "<" + W + " x float>",
              vi = "<" + W + " x i32>", vb = "<" + W + " x i1>";
  std::string mangle = "v" + W + "f32";
  auto row = [&](int r) { return std::to_string(r * w); };
  std::string ir;
  llvm::raw_string_ostream os(ir);
  os << "declare float @osl_test_exported_scale(float)\n"
     << "declare float @osl_test_hidden(float)\n"
     << "declare " << vf << " @llvm.sqrt." << mangle << "(" << vf << ")\n"
     << "declare void @llvm.masked.store." << mangle << ".p0(" << vf
     << ", ptr, i32, " << vb << ")\n"
     << "define void @" << name
     << "(ptr noalias %g, ptr noalias %out, i32 %nactive) {\n"
     << "entry:\n"
     << "  %ins = insertelement " << vi << " poison, i32 %nactive, i64 0\n"
     << "  %n = shufflevector " << vi << " %ins, " << vi << " poison, " << vi
     << " zeroinitializer\n"
     << "  %mask = icmp slt " << laneIndices(w) << ", %n\n"
     << "  %pu = getelementptr float, ptr %g, i64 " << row(33) << "\n"
     << "  %pv = getelementptr float, ptr %g, i64 " << row(34) << "\n"
     << "  %px = getelementptr float, ptr %g, i64 " << row(0) << "\n"
     << "  %u = load " << vf << ", ptr %pu, align 4\n"
     << "  %v = load " << vf << ", ptr %pv, align 4\n"
     << "  %x = load " << vf << ", ptr %px, align 4\n"
     << "  %uv = fmul " << vf << " %u, %v\n"
     << "  call void @llvm.masked.store." << mangle << ".p0(" << vf
     << " %uv, ptr %out, i32 4, " << vb << " %mask)\n"
     << "  %sq = call " << vf << " @llvm.sqrt." << mangle << "(" << vf
     << " %x)\n"
     << "  %k = call float @osl_test_exported_scale(float 1.5)\n"
     << "  %kins = insertelement " << vf << " poison, float %k, i64 0\n"
     << "  %ks = shufflevector " << vf << " %kins, " << vf << " poison, " << vi
     << " zeroinitializer\n"
     << "  %o1 = fmul " << vf << " %sq, %ks\n"
     << "  %p1 = getelementptr float, ptr %out, i64 " << row(1) << "\n"
     << "  call void @llvm.masked.store." << mangle << ".p0(" << vf
     << " %o1, ptr %p1, i32 4, " << vb << " %mask)\n"
     << "  %p2 = getelementptr float, ptr %out, i64 " << row(2) << "\n"
     << "  br label %loop\n"
     // A scalar loop over the active lanes calling the hidden function, the
     // way per-lane runtime calls look.
     << "loop:\n"
     << "  %i = phi i32 [ 0, %entry ], [ %inext, %body ]\n"
     << "  %more = icmp slt i32 %i, %nactive\n"
     << "  br i1 %more, label %body, label %exit\n"
     << "body:\n"
     << "  %vi = extractelement " << vf << " %v, i32 %i\n"
     << "  %h = call float @osl_test_hidden(float %vi)\n"
     << "  %pi = getelementptr float, ptr %p2, i32 %i\n"
     << "  store float %h, ptr %pi, align 4\n"
     << "  %inext = add i32 %i, 1\n"
     << "  br label %loop\n"
     << "exit:\n"
     << "  ret void\n"
     << "}\n";
  return os.str();
}

struct ParsedModule {
  std::unique_ptr<llvm::LLVMContext> context;
  std::unique_ptr<llvm::Module> module;
};

ParsedModule parse(const std::string &ir) {
  ParsedModule p;
  p.context = std::make_unique<llvm::LLVMContext>();
  llvm::SMDiagnostic diag;
  p.module = llvm::parseAssemblyString(ir, diag, *p.context);
  if (!p.module) {
    std::string msg;
    llvm::raw_string_ostream os(msg);
    diag.print("kernel", os);
    ADD_FAILURE() << os.str() << "\n" << ir;
  }
  return p;
}

std::unique_ptr<Jit> makeJit(Stats *stats = nullptr) {
  auto jit = Jit::create(stats);
  if (!jit) {
    ADD_FAILURE() << llvm::toString(jit.takeError());
    return nullptr;
  }
  std::pair<llvm::StringRef, void *> hidden[] = {
      {"osl_test_hidden", reinterpret_cast<void *>(&hiddenOffset)}};
  if (llvm::Error err = (*jit)->defineSymbols(hidden))
    ADD_FAILURE() << llvm::toString(std::move(err));
  return std::move(*jit);
}

} // namespace

TEST(Jit, RunsAnOptimizedKernelOverTheGrid) {
  Stats stats;
  std::unique_ptr<Jit> jit = makeJit(&stats);
  ASSERT_TRUE(jit);
  GridOptions o;
  o.xres = 61;
  o.yres = 47;
  o.threads = 2;
  for (int w : {1, 4, 8, 16}) {
    SCOPED_TRACE(w);
    std::string name = "kernel_w" + std::to_string(w);
    ParsedModule p = parse(kernelIR(w, name));
    ASSERT_TRUE(p.module);
    ASSERT_FALSE(llvm::errorToBool(jit->optimize(*p.module)));
    EXPECT_FALSE(p.module->getDataLayout().isDefault());
    EXPECT_EQ(p.module->getTargetTriple(),
              jit->targetMachine().getTargetTriple().str());
    ASSERT_FALSE(llvm::errorToBool(
        jit->addModule(std::move(p.module), std::move(p.context))));
    llvm::Expected<void *> address = jit->lookup(name);
    ASSERT_TRUE(bool(address)) << llvm::toString(address.takeError());
    auto kernel = reinterpret_cast<BatchKernel>(*address);

    ShadeResult r = shadeGrid(kernel, w, {{"uv", 1}, {"rest", 2}}, o);
    ASSERT_EQ(r.images.size(), 2u);
    int bad = 0;
    for (int y = 0; y < o.yres; ++y)
      for (int x = 0; x < o.xres; ++x) {
        size_t px = size_t(y) * o.xres + x;
        float u = (float)x / 60, v = (float)y / 46;
        bad += r.images[0][px] != u * v;
        bad += r.images[1][2 * px] != std::sqrt(u) * 3.0f;
        bad += r.images[1][2 * px + 1] != v + 0.25f;
      }
    EXPECT_EQ(bad, 0);
  }
  EXPECT_GT(stats.get("jit setup"), 0.0);
  EXPECT_GT(stats.get("llvm opt"), 0.0);
  EXPECT_GT(stats.get("jit link"), 0.0); // codegen of added IR happens at lookup
  std::string printed;
  llvm::raw_string_ostream os(printed);
  stats.print(os);
  EXPECT_NE(os.str().find("llvm opt"), std::string::npos);
  EXPECT_NE(os.str().find("total"), std::string::npos);
}

TEST(Jit, WideKernelUsesHostVectorRegisters) {
  ParsedModule p = parse(kernelIR(16, "wide"));
  ASSERT_TRUE(p.module);
  llvm::Expected<std::string> asmText = Jit::emitAssembly(*p.module);
  ASSERT_TRUE(bool(asmText)) << llvm::toString(asmText.takeError());
  EXPECT_NE(asmText->find("wide:"), std::string::npos);
  int width = Jit::hostMaxWidth();
  if (width == 16)
    EXPECT_NE(asmText->find("%zmm"), std::string::npos) << *asmText;
  else if (width == 8)
    EXPECT_NE(asmText->find("%ymm"), std::string::npos) << *asmText;
  // emitAssembly works on a clone: the module is untouched and still valid.
  EXPECT_TRUE(p.module->getTargetTriple().empty());
}

TEST(Jit, HostMaxWidthIsAVectorWidth) {
  int w = Jit::hostMaxWidth();
  EXPECT_TRUE(w == 4 || w == 8 || w == 16) << w;
}

TEST(Jit, MissingSymbolIsAnError) {
  std::unique_ptr<Jit> jit = makeJit();
  ASSERT_TRUE(jit);
  llvm::Expected<void *> address = jit->lookup("no_such_kernel");
  EXPECT_FALSE(bool(address));
  llvm::consumeError(address.takeError());
}

TEST(Jit, InvalidModuleIsRejectedByOptimize) {
  std::unique_ptr<Jit> jit = makeJit();
  ASSERT_TRUE(jit);
  llvm::LLVMContext context;
  llvm::Module module("bad", context);
  auto *type = llvm::FunctionType::get(llvm::Type::getVoidTy(context), false);
  auto *fn = llvm::Function::Create(type, llvm::Function::ExternalLinkage,
                                    "no_terminator", module);
  llvm::IRBuilder<> builder(llvm::BasicBlock::Create(context, "entry", fn));
  builder.CreateAlloca(builder.getFloatTy());
  llvm::Error err = jit->optimize(module);
  ASSERT_TRUE(bool(err));
  EXPECT_NE(llvm::toString(std::move(err)).find("invalid LLVM module"),
            std::string::npos);
}
