//===- OiioModule.h - OpenImageIO, loaded on first use ----------*- C++ -*-===//
//
// Private to OslImageIO. OpenImageIO brings ~260 shared libraries whose
// dynamic loading costs each process about 0.6 s (measured: an empty
// program linked with it takes 0.68 s, with libtiff and OpenEXR 0.01 s).
// Most runs write TIFF or EXR and use no texture, so OpenImageIO lives in
// the module libOslOiio.so, opened with dlopen when a texture is looked up
// or an image format other than TIFF and EXR is written or read.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRUNTIME_OIIOMODULE_H
#define OSLRUNTIME_OIIOMODULE_H

#include "OslAbi/EntryPoints.h"
#include "OslRuntime/ImageOutput.h"
#include "OslRuntime/TextureCall.h"

#include <cstdint>
#include <string>

namespace osl {

/// What the host gives the module: the runtime's functions it calls back.
struct OiioModuleHost {
  int32_t (*internString)(const char *text);
  /// The renderer's report of a failed request, printed in the shader's
  /// output as testshade prints it ("ERROR: text").
  void (*rendererError)(const char *text);
};

/// What the module provides. Images use testshade's spec (ImageOutput.h).
struct OiioModuleApi {
  /// An image open for writing, or nullptr with `error` set.
  /// `displayConvert`: rows go through colorconvert linear -> sRGB (with
  /// alpha), as testshade's display images do.
  void *(*openImage)(const std::string &path, const std::string &formatFrom, int xres,
                     int yres, int channels, const std::string &dataType,
                     bool integerValues, bool displayConvert, std::string &error);
  bool (*writeRows)(void *image, int rowBegin, int rowEnd, const float *data,
                    std::string &error);
  /// Closes and frees `image` (also after a failed write).
  bool (*closeImage)(void *image, std::string &error);
  bool (*readImage)(const std::string &path, ImageData &image, std::string &error);
  decltype(&osl_rt_texture) texture;
  decltype(&osl_rt_gettextureinfo) gettextureinfo;
  /// The file of `pattern`'s UDIM tile at (s, t) ("" where there is none),
  /// or nullptr where `pattern` is not a UDIM pattern. The text lasts.
  const char *(*udimTile)(const char *pattern, float s, float t);
  int (*textureFileErrors)();
  void (*setTextureCacheMegabytes)(float megabytes);
};

/// The module's one exported symbol.
using OiioModuleEntry = const OiioModuleApi *(*)(const OiioModuleHost *host);
constexpr const char *kOiioModuleEntry = "osl_oiio_module";
constexpr const char *kOiioModuleFile = "libOslOiio.so";

/// The module, loaded on the first call; nullptr with `error` set when it
/// cannot be loaded.
const OiioModuleApi *oiioModule(std::string &error);

/// The module if something already loaded it, else nullptr: for questions
/// (texture errors so far) that must not load it.
const OiioModuleApi *oiioModuleIfLoaded();

} // namespace osl

#endif // OSLRUNTIME_OIIOMODULE_H
