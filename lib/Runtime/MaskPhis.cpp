//===- MaskPhis.cpp - Loop masks kept as full-width lanes ------------------===//
#include "MaskPhis.h"

#include "llvm/ADT/DenseMap.h"
#include "llvm/ADT/PostOrderIterator.h"
#include "llvm/IR/CFG.h"
#include "llvm/IR/Constants.h"
#include "llvm/IR/DerivedTypes.h"
#include "llvm/IR/Function.h"
#include "llvm/IR/IRBuilder.h"
#include "llvm/IR/Instructions.h"

#include <vector>

namespace osl {
namespace {

bool isMask(llvm::Type *type) {
  auto *v = llvm::dyn_cast<llvm::FixedVectorType>(type);
  return v && v->getElementType()->isIntegerTy(1) && v->getNumElements() >= 4;
}

/// The mask operations carried in full-width lanes: phis and the logic
/// joining masks.
bool isMaskLogic(const llvm::Instruction &inst) {
  if (!isMask(inst.getType()))
    return false;
  if (llvm::isa<llvm::PHINode>(inst))
    return true;
  unsigned op = inst.getOpcode();
  return op == llvm::Instruction::And || op == llvm::Instruction::Or ||
         op == llvm::Instruction::Xor;
}

} // namespace

bool widenMaskPhis(llvm::Function &f) {
  std::vector<llvm::Instruction *> order;
  llvm::ReversePostOrderTraversal<llvm::Function *> rpo(&f);
  bool anyPhi = false;
  for (llvm::BasicBlock *block : rpo)
    for (llvm::Instruction &inst : *block)
      if (isMaskLogic(inst)) {
        order.push_back(&inst);
        anyPhi |= llvm::isa<llvm::PHINode>(inst);
      }
  if (!anyPhi)
    return false;
  llvm::DenseMap<llvm::Value *, llvm::Value *> wide;
  auto wideType = [&](llvm::Type *mask) {
    return llvm::FixedVectorType::get(llvm::Type::getInt32Ty(f.getContext()),
                                      llvm::cast<llvm::FixedVectorType>(mask)->getNumElements());
  };
  // A mask the rewrite does not make (a compare, a constant, an argument):
  // sign-extended once, right after it is defined.
  auto widen = [&](llvm::Value *v) -> llvm::Value * {
    if (llvm::Value *w = wide.lookup(v))
      return w;
    llvm::IRBuilder<> b(f.getContext());
    if (auto *inst = llvm::dyn_cast<llvm::Instruction>(v))
      b.SetInsertPoint(inst->getParent(), llvm::isa<llvm::PHINode>(inst)
                                               ? inst->getParent()->getFirstInsertionPt()
                                               : std::next(inst->getIterator()));
    else
      b.SetInsertPoint(f.getEntryBlock().getFirstInsertionPt());
    llvm::Value *w = b.CreateSExt(v, wideType(v->getType()));
    wide[v] = w;
    return w;
  };
  for (llvm::Instruction *inst : order)
    if (auto *phi = llvm::dyn_cast<llvm::PHINode>(inst))
      wide[phi] = llvm::PHINode::Create(wideType(phi->getType()), phi->getNumIncomingValues(),
                                        phi->getName() + ".lanes", phi->getIterator());
  for (llvm::Instruction *inst : order) {
    if (llvm::isa<llvm::PHINode>(inst))
      continue;
    llvm::IRBuilder<> b(inst);
    wide[inst] = b.CreateBinOp(llvm::cast<llvm::BinaryOperator>(inst)->getOpcode(),
                               widen(inst->getOperand(0)), widen(inst->getOperand(1)),
                               inst->getName() + ".lanes");
  }
  for (llvm::Instruction *inst : order)
    if (auto *phi = llvm::dyn_cast<llvm::PHINode>(inst)) {
      auto *widePhi = llvm::cast<llvm::PHINode>(wide[phi]);
      for (unsigned i = 0; i < phi->getNumIncomingValues(); ++i)
        widePhi->addIncoming(widen(phi->getIncomingValue(i)), phi->getIncomingBlock(i));
    }
  // Other users (selects, reductions, branches) read the mask narrowed
  // where it is made, as a sign test: the backend's compare then yields the
  // full-width lanes a blend takes (a truncation would pack them to 16 bits).
  // The wide logic was built just before the original (and folds to a
  // constant when both its masks are), so the test goes there too.
  for (llvm::Instruction *inst : order) {
    llvm::Value *w = wide[inst];
    llvm::IRBuilder<> b(inst->getParent(), llvm::isa<llvm::PHINode>(inst)
                                               ? inst->getParent()->getFirstInsertionPt()
                                               : inst->getIterator());
    inst->replaceAllUsesWith(
        b.CreateICmpSLT(w, llvm::Constant::getNullValue(w->getType()), inst->getName()));
  }
  for (llvm::Instruction *inst : order)
    inst->dropAllReferences();
  for (llvm::Instruction *inst : order)
    inst->eraseFromParent();
  return true;
}

} // namespace osl
