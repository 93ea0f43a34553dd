//===- Texture.h - The batched texture lookup's rows and codes ---*- C++ -*-===//
//
// Compiled kernels look textures up through osl_rt_texture (EntryPoints.h):
// one call per osl.texture and batch (per lane group when an option
// OpenImageIO takes once per call differs between lanes). Per-point values
// travel as rows of W floats in one block, laid out below, as the shader
// globals do; the options that must be uniform are arguments.
//
//===----------------------------------------------------------------------===//
#ifndef OSLABI_TEXTURE_H
#define OSLABI_TEXTURE_H

#include <cstdint>
#include <string_view>

namespace osl {

/// Row indices in a lookup's block of rows of W floats.
enum TextureRow : int32_t {
  kTextureCoordRow = 0,   ///< 3 rows: s, t (2D) or the point's (R's) x, y, z
  kTextureDerivRow = 3,   ///< 9 rows: ds/dx, dt/dx, ds/dy, dt/dy (2D); dP/dx,
                          ///< dP/dy, dP/dz (3D); dR/dx, dR/dy (environment)
  kTextureOptionRow = 12, ///< 11 rows: sblur, tblur, rblur, swidth, twidth,
                          ///< rwidth, fill, missingalpha, missingcolor r, g, b
  kTextureResultRow = 23, ///< 3 rows: the channels asked for
  kTextureAlphaRow = 26,  ///< the channel after them (alpha)
  kTextureErrorRow = 27,  ///< with kTextureWantsErrorMessage: a string handle
  kTextureFirstChannelRow = 28, ///< the first channel, an int per point
  kTextureDsRow = 29,     ///< 4 rows: d(result)/ds of each result row (2D)
  kTextureDtRow = 33,     ///< 4 rows: d(result)/dt of each result row (2D)
  kTextureFileRow = 37,   ///< with a null `file`: each lane's file name, a
                          ///< string handle (a name computed at run time)
  kTextureRows = 38,
};

enum TextureKind : int32_t { kTexture2D = 0, kTexture3D = 1, kTextureEnvironment = 2 };

enum TextureFlags : int32_t {
  kTextureHasMissingColor = 1, ///< missingcolor given: a missing file is no error
  kTextureHasMissingAlpha = 2,
  /// "errormessage" given: a failed lookup's error goes to the error row (no
  /// report), and "" where a lookup succeeds.
  kTextureWantsErrorMessage = 4,
  /// A 2D lookup's result has derivatives (osl-derivatives sets it where it
  /// reads the kTextureDsRow/kTextureDtRow slopes): without it OpenImageIO
  /// is not asked for them, which saves much of its filtering.
  kTextureWantsDerivatives = 8,
};

/// Where osl_rt_texture's `flags` is among its arguments (EntryPoints.h):
/// osl-derivatives adds kTextureWantsDerivatives to a call it differentiates.
inline constexpr unsigned kTextureFlagsArgument = 10;

/// OpenImageIO's wrap modes by name (its Tex::Wrap values); unknown names
/// are its default, as OpenImageIO decodes them.
constexpr int32_t textureWrapCode(std::string_view name) {
  return name == "black"                   ? 1
         : name == "clamp"                 ? 2
         : name == "periodic"              ? 3
         : name == "mirror"                ? 4
         : name == "periodic_pow2"         ? 5
         : name == "periodic_sharedborder" ? 6
                                           : 0;
}

/// OSL's interp names as OpenImageIO's Tex::InterpMode values; unknown
/// names keep the default, smart bicubic.
constexpr int32_t textureInterpCode(std::string_view name) {
  return name == "closest" ? 0 : name == "linear" ? 1 : name == "cubic" ? 2 : 3;
}

/// What gettextureinfo() answers with (its `kind` operand).
enum TextureInfoKind : int32_t {
  kTextureInfoInt = 0,
  kTextureInfoFloat = 1,
  kTextureInfoString = 2, // i32 handles of the runtime's string table
};

} // namespace osl

#endif // OSLABI_TEXTURE_H
