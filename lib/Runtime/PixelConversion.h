//===- PixelConversion.h - Stored pixel types, as OpenImageIO converts -*- C++ -*-===//
//
// Private to OslImageIO. The pixel types the native writers store, and the
// conversions from and to floats, made with OpenImageIO's inline
// convert_type (fmath.h) so values round and clamp exactly as they did when
// OpenImageIO wrote them.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRUNTIME_PIXELCONVERSION_H
#define OSLRUNTIME_PIXELCONVERSION_H

#include <cstddef>
#include <string>
#include <vector>

namespace osl::image {

enum class PixelType { UInt8, UInt16, Half, Float, Int32 };

size_t pixelTypeBytes(PixelType type);

/// -od's names the native writers store ("uint8", "uint16", "half",
/// "float"); false for the others, which OpenImageIO writes.
bool pixelTypeNamed(const std::string &name, PixelType &type);

/// `count` floats to `type` at `out`. With `integerPixels` the floats are
/// an int output's bits (Grid.h), converted as OpenImageIO converts ints
/// (to 32-bit ints exactly, to the other types as fractions of INT_MAX).
void convertPixels(const float *values, size_t count, bool integerPixels, PixelType type,
                   void *out);

/// `data` as float values: itself, or where `intBits` (an int output's bits
/// going to a format that stores it as floats, as testshade's EXRs) its ints
/// converted into `scratch`.
const float *floatValues(const float *data, size_t count, bool intBits,
                         std::vector<float> &scratch);

/// `count` stored values of `type` to floats, as OpenImageIO reads them.
void convertToFloat(const void *stored, PixelType type, size_t count, float *out);

} // namespace osl::image

#endif // OSLRUNTIME_PIXELCONVERSION_H
