//===- OiioModuleParts.h - Inside the OpenImageIO module --------*- C++ -*-===//
//
// The functions libOslOiio.so's table (OiioModule.h) is made of.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRUNTIME_OIIOMODULEPARTS_H
#define OSLRUNTIME_OIIOMODULEPARTS_H

#include "OiioModule.h"

namespace osl::oiio {

/// The host's callbacks, given when the module is opened.
const OiioModuleHost &host();

// Textures (TextureSystem.cpp): TextureCall.h's entry points.
void texture(const char *where, const char *file, const char *subimageName, int32_t subimage,
             int32_t kind, int32_t nchannels, int32_t swrap, int32_t twrap, int32_t rwrap,
             int32_t interp, int32_t flags, float *rows, int32_t width, uint32_t laneMask);
int32_t gettextureinfo(const char *file, const char *name, int32_t kind, int32_t count,
                       void *data);
const char *udimTile(const char *pattern, float s, float t);
int textureFileErrors();
void setTextureCacheMegabytes(float megabytes);

// Images (OiioImages.cpp).
void *openImage(const std::string &path, const std::string &formatFrom, int xres, int yres,
                int channels, const std::string &dataType, bool integerValues,
                bool displayConvert, std::string &error);
bool writeRows(void *image, int rowBegin, int rowEnd, const float *data, std::string &error);
bool closeImage(void *image, std::string &error);
bool readImage(const std::string &path, ImageData &image, std::string &error);

} // namespace osl::oiio

#endif // OSLRUNTIME_OIIOMODULEPARTS_H
