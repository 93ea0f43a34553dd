//===- TextureCall.h - Textures: the host side -------------------*- C++ -*-===//
//
// The runtime's settings and counts around osl_rt_texture (the lookup's
// rows and codes are OslAbi/Texture.h).
//
//===----------------------------------------------------------------------===//
#ifndef OSLRUNTIME_TEXTURECALL_H
#define OSLRUNTIME_TEXTURECALL_H

#include "OslAbi/Texture.h"

namespace osl {

/// Sets the shared texture cache's size (the default is OpenImageIO's).
void setTextureCacheMegabytes(float megabytes);

/// How many texture files could not be read (each is reported once), for a
/// tool's exit status.
int textureFileErrors();

} // namespace osl

#endif // OSLRUNTIME_TEXTURECALL_H
