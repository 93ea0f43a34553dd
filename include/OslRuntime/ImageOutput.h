//===- ImageOutput.h - Write/read shaded images -----------------*- C++ -*-===//
//
// The grid driver's images. TIFF and EXR are written with libtiff and
// OpenEXR, other formats with OpenImageIO, loaded on first use. Their
// headers need C++ exceptions and Debian's LLVM is built without, so the
// implementation lives in its own library (OslImageIO) and this header
// names no library's type.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRUNTIME_IMAGEOUTPUT_H
#define OSLRUNTIME_IMAGEOUTPUT_H

#include <memory>
#include <string>
#include <vector>

namespace osl {

/// Writes xres x yres pixels of `channels` interleaved floats to `path`; the
/// format follows the extension (exr, tif, png, ...) and OIIO converts the
/// float data for 8/16-bit formats as OpenImageIO does. Channels are named R,G,B,A then
/// channel4..., and a single channel is named Y, as OSL's testshade does.
/// The path "null" discards the image (testshade's `-o NAME null`).
/// `dataType` is the stored type as testshade's -od names it (uint8, half,
/// float...); empty stores floats. `integerValues` marks an int output
/// (whole numbers), written as testshade writes one: int pixels in a format
/// that stores 32-bit ints (TIFF), or converted to `dataType` as OIIO
/// converts ints (fractions of INT_MAX); without `dataType`, a format without
/// ints (EXR) stores the values as floats. `asTestshade` writes display
/// images as testshade does (displayEncoded). Returns false with a message
/// in `error` on failure.
bool writeImage(const std::string &path, int xres, int yres, int channels,
                const float *data, std::string &error,
                const std::string &dataType = "", bool integerValues = false,
                bool asTestshade = false);

/// Whether testshade writes `path` as a display image encoded here: a PNG or
/// JPEG of 1 or 3 channels holds its linear values sRGB-encoded, 8 bits,
/// whatever -od says (OSL 1.13's testshade converts linear to sRGB for those
/// formats; an int output is first a fraction of INT_MAX, as OpenImageIO
/// converts ints). With other channel counts, alpha among them, OpenImageIO
/// converts them as for testshade (asTestshade).
bool displayEncoded(const std::string &path, int channels);

/// `count` values (an int output's bits where `intBits`) sRGB-encoded into
/// `out`, as testshade's display images hold them.
void encodeForDisplay(const float *values, size_t count, bool intBits, float *out);

/// The name writeImage and ImageStream write `path` under until it is
/// complete.
std::string partialImagePath(const std::string &path);

/// An image written a band of rows at a time, so an image larger than
/// memory never has to be held whole (osl-run streams huge grids). Same
/// file contents as writeImage. `path` is written under a temporary name
/// and renamed by close(), so a run that stops half way leaves no partial
/// file at `path`.
class ImageStream {
public:
  ImageStream();
  ~ImageStream(); // an unclosed stream removes its temporary file
  ImageStream(ImageStream &&) noexcept;
  ImageStream &operator=(ImageStream &&) noexcept;

  bool open(const std::string &path, int xres, int yres, int channels,
            std::string &error, const std::string &dataType = "",
            bool integerValues = false, bool asTestshade = false);
  /// Rows [rowBegin, rowEnd), xres * channels floats each; bands must come
  /// in order.
  bool writeRows(int rowBegin, int rowEnd, const float *data, std::string &error);
  bool close(std::string &error);
  /// The file being written until close(): for a signal handler that must
  /// remove it.
  const char *temporaryPath() const;

private:
  bool openStream(const std::string &path, int xres, int yres, int channels,
                  std::string &error, const std::string &dataType, bool integerValues,
                  bool displayConvert);
  struct Impl;
  std::unique_ptr<Impl> impl;
};

/// A float image read back, pixel-major with channels interleaved.
struct ImageData {
  int xres = 0, yres = 0, channels = 0;
  std::vector<std::string> channelNames;
  std::vector<float> pixels;
};

/// Reads the first subimage of `path` as floats. For tests and comparisons
/// against reference images.
bool readImage(const std::string &path, ImageData &image, std::string &error);

/// readImage for the files it reads without OpenImageIO: TIFF and EXR of
/// one image in the common layouts. False with `error` empty for others.
bool readImageNatively(const std::string &path, ImageData &image, std::string &error);

} // namespace osl

#endif // OSLRUNTIME_IMAGEOUTPUT_H
