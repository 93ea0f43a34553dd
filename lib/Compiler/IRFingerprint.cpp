//===- IRFingerprint.cpp - A stable hash of an operation's IR -------------===//
#include "IRFingerprint.h"

#include "mlir/IR/Block.h"
#include "mlir/IR/Region.h"
#include "llvm/ADT/StringExtras.h"
#include "llvm/Support/raw_ostream.h"
#include "llvm/Support/xxhash.h"

using namespace osl;

namespace {

/// The bytes the hash covers.
struct Stream {
  std::string bytes;
  void add(uint64_t v) { bytes.append(reinterpret_cast<const char *>(&v), sizeof v); }
  void add(llvm::StringRef s) {
    add(uint64_t(s.size()));
    bytes.append(s.data(), s.size());
  }
};

} // namespace

uint64_t IRFingerprint::hashOf(const void *uniqued,
                               llvm::function_ref<void(llvm::raw_ostream &)> print) {
  auto [it, inserted] = printed.try_emplace(uniqued, 0);
  if (inserted) {
    std::string text;
    llvm::raw_string_ostream os(text);
    print(os);
    it->second = llvm::xxh3_64bits(text);
  }
  return it->second;
}

uint64_t IRFingerprint::hashOf(mlir::Type type) {
  return hashOf(type.getAsOpaquePointer(), [&](llvm::raw_ostream &os) { os << type; });
}

uint64_t IRFingerprint::hashOf(mlir::Attribute attr) {
  return hashOf(attr.getAsOpaquePointer(), [&](llvm::raw_ostream &os) { os << attr; });
}

std::string IRFingerprint::of(mlir::Operation *root) {
  Stream s;
  // Values and blocks by their order of definition, as the printer names them.
  llvm::DenseMap<mlir::Value, uint64_t> valueIds;
  llvm::DenseMap<mlir::Block *, uint64_t> blockIds;
  auto define = [&](mlir::Value v) {
    valueIds.try_emplace(v, valueIds.size());
    s.add(hashOf(v.getType()));
  };
  std::function<void(mlir::Operation *)> visit = [&](mlir::Operation *op) {
    s.add(op->getName().getStringRef());
    s.add(uint64_t(op->getNumOperands()));
    for (mlir::Value operand : op->getOperands()) {
      auto it = valueIds.find(operand);
      // A value from outside `root` is named by its type alone.
      s.add(it == valueIds.end() ? ~uint64_t(0) : it->second);
      s.add(hashOf(operand.getType()));
    }
    s.add(hashOf(op->getRawDictionaryAttrs()));
    if (op->getPropertiesStorageSize())
      s.add(hashOf(op->getPropertiesAsAttribute()));
    s.add(uint64_t(op->getNumSuccessors()));
    for (mlir::Block *successor : op->getSuccessors())
      s.add(blockIds.lookup(successor));
    s.add(uint64_t(op->getNumResults()));
    for (mlir::Value result : op->getResults())
      define(result);
    s.add(uint64_t(op->getNumRegions()));
    for (mlir::Region &region : op->getRegions()) {
      s.add(uint64_t(region.getBlocks().size()));
      // Branches may name blocks defined after them.
      for (mlir::Block &block : region)
        blockIds.try_emplace(&block, blockIds.size());
      for (mlir::Block &block : region) {
        s.add(blockIds.lookup(&block));
        s.add(uint64_t(block.getNumArguments()));
        for (mlir::BlockArgument arg : block.getArguments())
          define(arg);
        s.add(uint64_t(block.getOperations().size()));
        for (mlir::Operation &nested : block)
          visit(&nested);
      }
    }
  };
  visit(root);
  llvm::XXH128_hash_t h = llvm::xxh3_128bits(llvm::arrayRefFromStringRef(s.bytes));
  return llvm::utohexstr(h.high64, /*LowerCase=*/true, 16) +
         llvm::utohexstr(h.low64, /*LowerCase=*/true, 16);
}
