//===- MaskPhisTest.cpp - Loop masks carried as full-width lanes -----------===//
//
// A varying while loop in the shape the compiler emits: its lane mask is a
// phi of <8 x i1> joined with the loop test by `and`. widenMaskPhis carries
// it as <8 x i32>; the loop computes the same lanes, checked by running it.
//
//===----------------------------------------------------------------------===//

#include "MaskPhis.h"
#include "OslRuntime/Jit.h"

#include "llvm/AsmParser/Parser.h"
#include "llvm/IR/Instructions.h"
#include "llvm/IR/LLVMContext.h"
#include "llvm/IR/Module.h"
#include "llvm/IR/Verifier.h"
#include "llvm/Support/SourceMgr.h"
#include "llvm/Support/raw_ostream.h"

#include "gtest/gtest.h"

#include <array>

using namespace osl;

namespace {

/// steps(x): per lane, how many halvings bring x to 0 or below, and x
/// divided by 3 that many times, for the lanes of `live`.
constexpr const char *kLoopIR = R"(
define void @steps(ptr %in, ptr %out, ptr %divided, <8 x i1> %live) {
entry:
  %x0 = load <8 x i32>, ptr %in, align 4
  br label %test
test:
  %x = phi <8 x i32> [ %x0, %entry ], [ %x.next, %body ]
  %y = phi <8 x i32> [ %x0, %entry ], [ %y.next, %body ]
  %n = phi <8 x i32> [ zeroinitializer, %entry ], [ %n.next, %body ]
  %mask = phi <8 x i1> [ %live, %entry ], [ %active, %body ]
  %positive = icmp sgt <8 x i32> %x, zeroinitializer
  %active = and <8 x i1> %mask, %positive
  %any = call i1 @llvm.vector.reduce.or.v8i1(<8 x i1> %active)
  br i1 %any, label %body, label %done
body:
  %half = sdiv <8 x i32> %x, <i32 2, i32 2, i32 2, i32 2, i32 2, i32 2, i32 2, i32 2>
  %third = sdiv <8 x i32> %y, <i32 3, i32 3, i32 3, i32 3, i32 3, i32 3, i32 3, i32 3>
  %n1 = add <8 x i32> %n, <i32 1, i32 1, i32 1, i32 1, i32 1, i32 1, i32 1, i32 1>
  %x.next = select <8 x i1> %active, <8 x i32> %half, <8 x i32> %x
  %y.next = select <8 x i1> %active, <8 x i32> %third, <8 x i32> %y
  %n.next = select <8 x i1> %active, <8 x i32> %n1, <8 x i32> %n
  br label %test
done:
  store <8 x i32> %n, ptr %out, align 4
  store <8 x i32> %y, ptr %divided, align 4
  ret void
}
declare i1 @llvm.vector.reduce.or.v8i1(<8 x i1>)

define void @run(ptr %in, ptr %out, ptr %divided, i32 %liveBits) {
  %bits = trunc i32 %liveBits to i8
  %live = bitcast i8 %bits to <8 x i1>
  call void @steps(ptr %in, ptr %out, ptr %divided, <8 x i1> %live)
  ret void
}
)";

int countPhis(llvm::Function &f, unsigned elementBits) {
  int n = 0;
  for (llvm::BasicBlock &block : f)
    for (llvm::PHINode &phi : block.phis())
      if (auto *v = llvm::dyn_cast<llvm::FixedVectorType>(phi.getType()))
        n += v->getElementType()->isIntegerTy(elementBits);
  return n;
}

} // namespace

TEST(MaskPhis, LoopMaskBecomesFullWidthLanes) {
  auto context = std::make_unique<llvm::LLVMContext>();
  llvm::SMDiagnostic diag;
  std::unique_ptr<llvm::Module> module = llvm::parseAssemblyString(kLoopIR, diag, *context);
  ASSERT_TRUE(module);
  llvm::Function &steps = *module->getFunction("steps");
  ASSERT_EQ(countPhis(steps, 1), 1);
  ASSERT_EQ(countPhis(steps, 32), 3);

  EXPECT_TRUE(widenMaskPhis(steps));
  std::string errors;
  llvm::raw_string_ostream os(errors);
  ASSERT_FALSE(llvm::verifyFunction(steps, &os)) << errors;
  EXPECT_EQ(countPhis(steps, 1), 0);
  EXPECT_EQ(countPhis(steps, 32), 4);
  // No mask logic is left on <8 x i1>: the `and` is on the wide lanes.
  for (llvm::BasicBlock &block : steps)
    for (llvm::Instruction &inst : block)
      if (inst.getOpcode() == llvm::Instruction::And)
        EXPECT_TRUE(inst.getType()->getScalarType()->isIntegerTy(32));
  // A function without mask phis is left alone.
  EXPECT_FALSE(widenMaskPhis(*module->getFunction("run")));

  auto jit = Jit::create();
  ASSERT_TRUE(bool(jit)) << llvm::toString(jit.takeError());
  ASSERT_FALSE(llvm::errorToBool((*jit)->optimize(*module)));
  ASSERT_FALSE(llvm::errorToBool((*jit)->addModule(std::move(module), std::move(context))));
  llvm::Expected<void *> address = (*jit)->lookup("run");
  ASSERT_TRUE(bool(address)) << llvm::toString(address.takeError());
  auto run = reinterpret_cast<void (*)(const int32_t *, int32_t *, int32_t *, int32_t)>(*address);

  std::array<int32_t, 8> in = {0, 1, 7, -5, 1000, 1 << 30, 3, 64};
  for (int32_t live : {0xff, 0x5a, 0x00}) {
    SCOPED_TRACE(live);
    std::array<int32_t, 8> out{}, divided{};
    run(in.data(), out.data(), divided.data(), live);
    for (int lane = 0; lane < 8; ++lane) {
      int32_t x = in[size_t(lane)], y = x, n = 0;
      if (live >> lane & 1)
        for (; x > 0; ++n)
          x /= 2, y /= 3;
      EXPECT_EQ(out[size_t(lane)], n) << "lane " << lane;
      EXPECT_EQ(divided[size_t(lane)], y) << "lane " << lane;
    }
  }
}

// Mask logic on two constant masks widens to a constant (IRBuilder folds
// it): its users still get a sign test, with nothing left dangling.
TEST(MaskPhis, LogicOnConstantMasksFolds) {
  constexpr const char *kIR = R"(
define <8 x i1> @f(<8 x i1> %in, i1 %again) {
entry:
  br label %loop
loop:
  %mask = phi <8 x i1> [ %in, %entry ], [ %next, %loop ]
  %fixed = xor <8 x i1> zeroinitializer, <i1 true, i1 false, i1 true, i1 false, i1 true, i1 false, i1 true, i1 false>
  %next = and <8 x i1> %mask, %fixed
  br i1 %again, label %loop, label %done
done:
  ret <8 x i1> %fixed
}
)";
  llvm::LLVMContext context;
  llvm::SMDiagnostic diag;
  std::unique_ptr<llvm::Module> module = llvm::parseAssemblyString(kIR, diag, context);
  ASSERT_TRUE(module);
  llvm::Function &f = *module->getFunction("f");
  EXPECT_TRUE(widenMaskPhis(f));
  std::string errors;
  llvm::raw_string_ostream os(errors);
  EXPECT_FALSE(llvm::verifyFunction(f, &os)) << errors;
  EXPECT_EQ(countPhis(f, 1), 0);
  auto *ret = llvm::cast<llvm::ReturnInst>(f.back().getTerminator());
  EXPECT_TRUE(llvm::isa<llvm::Constant>(ret->getReturnValue()));
}
