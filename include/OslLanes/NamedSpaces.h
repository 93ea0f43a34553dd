//===- NamedSpaces.h - testshade's coordinate systems -----------*- C++ -*-===//
//
// The matrices between named spaces. The fixed spaces ("common", "world",
// "camera", "shader", "object", "myspace") are what osl.transform lowers;
// the camera's projection spaces ("screen", "NDC", "raster") depend on the
// image size, so only the front end, which is told the size as a compile
// option, resolves them (into matrix arithmetic).
//
//===----------------------------------------------------------------------===//
#ifndef OSLLANES_NAMEDSPACES_H
#define OSLLANES_NAMEDSPACES_H

#include "OslLanes/LibraryBuilders.h"

namespace mlir::osl {

/// testshade's camera: world = camera, a 90 degree perspective projection
/// with near 0.1 and far 1000 onto the screen window [-1,1]^2, over an
/// image of xres x yres pixels (its -g grid).
struct CameraImage {
  int xres = 256;
  int yres = 256;
};

/// "screen", "NDC" or "raster": spaces the renderer knows only as
/// destinations.
bool isProjectionSpace(StringRef space);

/// The matrix from `from` to `to` where `to` may also be a projection
/// space of `camera`; nullopt for a name testshade does not know.
std::optional<Matrix44> namedSpaceTransform(StringRef from, StringRef to,
                                            const CameraImage &camera);

} // namespace mlir::osl

#endif // OSLLANES_NAMEDSPACES_H
