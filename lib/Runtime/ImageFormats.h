//===- ImageFormats.h - Image file writers and readers ----------*- C++ -*-===//
//
// Private to OslImageIO. TIFF and OpenEXR, the formats testshade's outputs
// and OSL's references use, are written and read with libtiff and OpenEXR
// directly: linking OpenImageIO costs every osl-run about 0.6 s of dynamic
// loading (its ~260 libraries), measured, so OpenImageIO lives in a module
// loaded on first use (OiioModule.h) for the other formats and textures.
// Pixel conversions use OpenImageIO's own inline code (fmath.h), so the
// files hold what OpenImageIO would have written.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRUNTIME_IMAGEFORMATS_H
#define OSLRUNTIME_IMAGEFORMATS_H

#include "OslRuntime/ImageOutput.h"

#include <memory>
#include <string>
#include <vector>

namespace osl::image {

/// What an output image stores: testshade's spec.
struct WriteSpec {
  int xres = 0, yres = 0, channels = 0;
  std::string dataType;       ///< -od's name; empty: floats
  bool intBits = false;       ///< the floats are an int output's bits (Grid.h)
  bool integerPixels = false; ///< written as ints (an int output, where the format has them)
  /// Written as testshade writes a display image (ImageOutput.h's
  /// displayEncoded) of a channel count the native encoding does not
  /// cover: OpenImageIO's colorconvert, with alpha, then 8 bits.
  bool displayConvert = false;
};

/// testshade's channel names: R, G, B, A, then channel4...; Y alone.
std::vector<std::string> channelNames(int channels);

/// One image being written, bands of rows in order.
class Writer {
public:
  virtual ~Writer() = default;
  /// Rows [rowBegin, rowEnd), xres * channels floats each.
  virtual bool writeRows(int rowBegin, int rowEnd, const float *data, std::string &error) = 0;
  virtual bool close(std::string &error) = 0;
};

/// The native writers: nullptr with `error` empty when the spec's data type
/// is one they leave to OpenImageIO, with `error` set when the file fails.
std::unique_ptr<Writer> openTiff(const std::string &path, const WriteSpec &spec,
                                 std::string &error);
std::unique_ptr<Writer> openExr(const std::string &path, const WriteSpec &spec,
                                std::string &error);
std::unique_ptr<Writer> openPng(const std::string &path, const WriteSpec &spec,
                                std::string &error);
/// Any format OpenImageIO writes, through the module; `formatFrom` names
/// the format by its extension when `path` is a temporary name.
std::unique_ptr<Writer> openWithOiio(const std::string &path, const std::string &formatFrom,
                                     const WriteSpec &spec, std::string &error);

/// What a native reader made of a file.
enum class ReadResult { Read, Failed, Unsupported };

/// The first subimage as floats, converted as OpenImageIO converts them.
/// Unsupported: a layout the native reader leaves to OpenImageIO (tiles,
/// palettes, several subimages or mip levels, ...).
ReadResult readTiff(const std::string &path, ImageData &image, std::string &error);
ReadResult readExr(const std::string &path, ImageData &image, std::string &error);
bool readWithOiio(const std::string &path, ImageData &image, std::string &error);

/// The format a path's extension names among the native ones.
enum class NativeFormat { None, Tiff, Exr, Png };
/// `path`'s extension in lower case, without the dot ("" if none).
std::string lowerExtension(const std::string &path);
NativeFormat nativeFormat(const std::string &path);

} // namespace osl::image

#endif // OSLRUNTIME_IMAGEFORMATS_H
