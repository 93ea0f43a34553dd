//===- ImageOutput.h - Write/read shaded images with OpenImageIO -*- C++ -*-===//
//
// The only interface to OpenImageIO from the grid driver. OIIO's headers need
// C++ exceptions and Debian's LLVM is built without, so the implementation
// lives in its own library (OslImageIO) and this header names no OIIO type.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRUNTIME_IMAGEOUTPUT_H
#define OSLRUNTIME_IMAGEOUTPUT_H

#include <string>
#include <vector>

namespace osl {

/// Writes xres x yres pixels of `channels` interleaved floats to `path`; the
/// format follows the extension (exr, tif, png, ...) and OIIO converts the
/// float data for 8/16-bit formats. Channels are named R,G,B,A then
/// channel4..., and a single channel is named Y, as OSL's testshade does.
/// The path "null" discards the image (testshade's `-o NAME null`).
/// `dataType` is the stored type as testshade's -od names it (uint8, half,
/// float...); empty stores floats. Returns false with a message in `error`
/// on failure.
bool writeImage(const std::string &path, int xres, int yres, int channels,
                const float *data, std::string &error,
                const std::string &dataType = "");

/// A float image read back, pixel-major with channels interleaved.
struct ImageData {
  int xres = 0, yres = 0, channels = 0;
  std::vector<std::string> channelNames;
  std::vector<float> pixels;
};

/// Reads the first subimage of `path` as floats. For tests and comparisons
/// against reference images.
bool readImage(const std::string &path, ImageData &image, std::string &error);

} // namespace osl

#endif // OSLRUNTIME_IMAGEOUTPUT_H
