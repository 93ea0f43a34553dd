//===- LibraryRegion.h - Library routines marked for outlining --*- C++ -*-===//
//
// A library routine (noise, Gabor noise) is lowered inline, inside an
// scf.execute_region marked `osl.library = "name"`: osl-derivatives can
// still differentiate through it (it inlines the region it needs), and
// osl-outline-library then makes each routine one function per kernel,
// which the JIT compiles once and caches as an object across shaders.
//
//===----------------------------------------------------------------------===//
#ifndef OSLLANES_LIBRARYREGION_H
#define OSLLANES_LIBRARYREGION_H

#include "mlir/Dialect/SCF/IR/SCF.h"
#include "mlir/IR/Builders.h"

namespace mlir::osl {

/// The attribute naming a library region's routine.
constexpr const char *kLibraryAttr = "osl.library";

/// Emits `build`'s code in a region marked as library routine `name`; the
/// region's results (of `resultTypes`) are what `build` returns.
SmallVector<Value>
buildLibraryRegion(OpBuilder &b, Location loc, StringRef name, TypeRange resultTypes,
                   function_ref<SmallVector<Value>(OpBuilder &)> build);

/// The library region defining `v`, if any.
scf::ExecuteRegionOp libraryRegionDefining(Value v);

/// Moves a library region's code in place of the region and returns what
/// replaces its results.
SmallVector<Value> inlineLibraryRegion(scf::ExecuteRegionOp region);

} // namespace mlir::osl

#endif // OSLLANES_LIBRARYREGION_H
