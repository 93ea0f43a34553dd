//===- LibraryRegion.cpp - Library routines marked for outlining ----------===//
#include "OslLanes/LibraryRegion.h"

using namespace mlir;

SmallVector<Value>
osl::buildLibraryRegion(OpBuilder &b, Location loc, StringRef name, TypeRange resultTypes,
                        function_ref<SmallVector<Value>(OpBuilder &)> build) {
  auto region = b.create<scf::ExecuteRegionOp>(loc, resultTypes);
  region->setAttr(kLibraryAttr, b.getStringAttr(name));
  OpBuilder::InsertionGuard guard(b);
  b.createBlock(&region.getRegion());
  SmallVector<Value> results = build(b);
  b.create<scf::YieldOp>(loc, results);
  return SmallVector<Value>(region.getResults());
}

scf::ExecuteRegionOp osl::libraryRegionDefining(Value v) {
  auto region = v.getDefiningOp<scf::ExecuteRegionOp>();
  return region && region->hasAttr(kLibraryAttr) ? region : scf::ExecuteRegionOp();
}

SmallVector<Value> osl::inlineLibraryRegion(scf::ExecuteRegionOp region) {
  // The builders emit structured control flow only: one block.
  Block &body = region.getRegion().front();
  auto yield = cast<scf::YieldOp>(body.getTerminator());
  SmallVector<Value> results(yield.getOperands());
  yield.erase();
  region->getBlock()->getOperations().splice(Block::iterator(region), body.getOperations());
  region.replaceAllUsesWith(results);
  region.erase();
  return results;
}
