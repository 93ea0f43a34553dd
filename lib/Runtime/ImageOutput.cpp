//===- ImageOutput.cpp - Write/read shaded images -------------------------===//
//
// TIFF and EXR, and PNG when written, go through the native code
// (ImageFormats.h), everything else through OpenImageIO in its module
// (OiioModule.h).
//
//===----------------------------------------------------------------------===//
#include "OslRuntime/ImageOutput.h"
#include "ImageFormats.h"
#include "OslRuntime/Grid.h"

#include <OpenImageIO/color.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cerrno>
#include <cstdio>
#include <cstring>

namespace osl {

namespace image {

std::vector<std::string> channelNames(int channels) {
  static const char *const kRGBA[] = {"R", "G", "B", "A"};
  std::vector<std::string> names;
  for (int c = 0; c < channels; ++c)
    names.push_back(channels == 1 ? std::string("Y")
                    : c < 4       ? std::string(kRGBA[c])
                                  : "channel" + std::to_string(c));
  return names;
}

std::string lowerExtension(const std::string &path) {
  size_t dot = path.rfind('.');
  if (dot == std::string::npos || path.find('/', dot) != std::string::npos)
    return "";
  std::string extension = path.substr(dot + 1);
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return extension;
}

NativeFormat nativeFormat(const std::string &path) {
  std::string extension = lowerExtension(path);
  if (extension == "tif" || extension == "tiff")
    return NativeFormat::Tiff;
  if (extension == "exr")
    return NativeFormat::Exr;
  if (extension == "png")
    return NativeFormat::Png;
  return NativeFormat::None;
}

} // namespace image

namespace {

/// A writer for `path`, in the format `formatFrom`'s extension names.
std::unique_ptr<image::Writer> openWriter(const std::string &path, const std::string &formatFrom,
                                          const image::WriteSpec &spec, std::string &error) {
  if (spec.xres <= 0 || spec.yres <= 0 || spec.channels <= 0) {
    error = "cannot write an empty image to " + formatFrom;
    return nullptr;
  }
  std::unique_ptr<image::Writer> writer;
  if (spec.displayConvert)
    return image::openWithOiio(path, formatFrom, spec, error);
  switch (image::nativeFormat(formatFrom)) {
  case image::NativeFormat::Tiff: writer = image::openTiff(path, spec, error); break;
  case image::NativeFormat::Exr: writer = image::openExr(path, spec, error); break;
  case image::NativeFormat::Png: writer = image::openPng(path, spec, error); break;
  case image::NativeFormat::None: break;
  }
  if (writer || !error.empty())
    return writer;
  return image::openWithOiio(path, formatFrom, spec, error);
}

image::WriteSpec specOf(int xres, int yres, int channels, const std::string &dataType,
                        bool integerValues) {
  image::WriteSpec spec;
  spec.xres = xres;
  spec.yres = yres;
  spec.channels = channels;
  spec.dataType = dataType;
  spec.intBits = integerValues;
  spec.integerPixels = integerValues;
  return spec;
}

} // namespace

namespace {
/// The formats testshade writes as display images.
bool displayFormat(const std::string &path) {
  std::string extension = image::lowerExtension(path);
  return extension == "png" || extension == "jpg" || extension == "jpeg";
}
} // namespace

bool displayEncoded(const std::string &path, int channels) {
  return (channels == 1 || channels == 3) && displayFormat(path);
}

namespace {
/// An int output's value (its bits) as OpenImageIO converts an int to a
/// float: a fraction of INT_MAX.
float intFraction(float bits) { return float(intOutputValue(bits)) * (1.0f / 2147483647.0f); }
} // namespace

void encodeForDisplay(const float *values, size_t count, bool intBits, float *out) {
  for (size_t i = 0; i < count; ++i) {
    float linear = intBits ? intFraction(values[i]) : values[i];
    // Clamped first (NaN to 0): 8 bits clamp anyway. OpenImageIO's own
    // curve (its approximate pow), which testshade's conversion runs: the
    // exact one rounds some values to the next 8-bit step.
    float x = linear >= 0.0f ? std::min(linear, 1.0f) : 0.0f;
    out[i] = OIIO::linear_to_sRGB(OIIO::simd::vfloat4(x))[0];
  }
}

bool writeImage(const std::string &path, int xres, int yres, int channels,
                const float *data, std::string &error, const std::string &dataType,
                bool integerValues, bool asTestshade) {
  // testshade's `-o NAME null` shades the output but writes nothing.
  if (path == "null")
    return true;
  if (!data) {
    error = "cannot write an empty image to " + path;
    return false;
  }
  // Written beside, then renamed (ImageStream): an image that cannot be
  // written leaves no file, and an earlier image of that name stays as it was.
  ImageStream stream;
  if (!stream.open(path, xres, yres, channels, error, dataType, integerValues, asTestshade) ||
      !stream.writeRows(0, yres, data, error))
    return false; // the stream removes what it began
  return stream.close(error);
}

std::string partialImagePath(const std::string &path) { return path + ".part"; }

struct ImageStream::Impl {
  std::unique_ptr<image::Writer> writer;
  std::string path, temporary;
  int xres = 0, channels = 0;
  /// A testshade display image: rows are encoded on the way (`encode`,
  /// displayEncoded), or given to OpenImageIO's conversion as floats
  /// (`fractions`: an int output's bits as fractions of INT_MAX); `intBits`:
  /// the rows are an int output's.
  bool encode = false, fractions = false, intBits = false;
  std::vector<float> encoded;
};

ImageStream::ImageStream() = default;
ImageStream::ImageStream(ImageStream &&) noexcept = default;
ImageStream &ImageStream::operator=(ImageStream &&) noexcept = default;

ImageStream::~ImageStream() {
  if (impl && impl->writer) {
    std::string ignored;
    impl->writer->close(ignored);
    std::remove(impl->temporary.c_str());
  }
}

bool ImageStream::open(const std::string &path, int xres, int yres, int channels,
                       std::string &error, const std::string &dataType,
                       bool integerValues, bool asTestshade) {
  impl = std::make_unique<Impl>();
  impl->path = path;
  impl->xres = xres;
  impl->channels = channels;
  if (asTestshade && displayEncoded(path, channels)) {
    impl->encode = true;
    impl->intBits = integerValues;
    return openStream(path, xres, yres, channels, error, "uint8", false, false);
  }
  // Other channel counts (alpha): OpenImageIO converts them as for testshade,
  // from floats.
  bool convert = asTestshade && displayFormat(path);
  impl->fractions = convert && integerValues;
  impl->intBits = integerValues;
  return openStream(path, xres, yres, channels, error, convert ? "uint8" : dataType,
                    integerValues && !convert, convert);
}

bool ImageStream::openStream(const std::string &path, int xres, int yres, int channels,
                             std::string &error, const std::string &dataType,
                             bool integerValues, bool displayConvert) {
  // Same directory, so the rename is atomic; the format comes from `path`.
  impl->temporary = partialImagePath(path);
  image::WriteSpec spec = specOf(xres, yres, channels, dataType, integerValues);
  spec.displayConvert = displayConvert;
  impl->writer = openWriter(impl->temporary, path, spec, error);
  if (!impl->writer) // (a format refusing the channels may have created it)
    std::remove(impl->temporary.c_str());
  return impl->writer != nullptr;
}

bool ImageStream::writeRows(int rowBegin, int rowEnd, const float *data, std::string &error) {
  if (!impl || !impl->writer) {
    error = "image stream is not open";
    return false;
  }
  if (impl->encode || impl->fractions) {
    size_t count = size_t(rowEnd - rowBegin) * impl->xres * impl->channels;
    impl->encoded.resize(count);
    if (impl->encode)
      encodeForDisplay(data, count, impl->intBits, impl->encoded.data());
    else
      std::transform(data, data + count, impl->encoded.begin(), intFraction);
    data = impl->encoded.data();
  }
  return impl->writer->writeRows(rowBegin, rowEnd, data, error);
}

bool ImageStream::close(std::string &error) {
  if (!impl || !impl->writer)
    return true;
  bool closed = impl->writer->close(error);
  impl->writer.reset();
  if (closed && std::rename(impl->temporary.c_str(), impl->path.c_str()) != 0) {
    error = "cannot rename " + impl->temporary + " to " + impl->path + ": " +
            std::strerror(errno);
    closed = false;
  }
  if (!closed)
    std::remove(impl->temporary.c_str());
  return closed;
}

const char *ImageStream::temporaryPath() const {
  return impl && impl->writer ? impl->temporary.c_str() : nullptr;
}

namespace {

image::ReadResult readNative(const std::string &path, ImageData &image, std::string &error) {
  switch (image::nativeFormat(path)) {
  case image::NativeFormat::Tiff: return image::readTiff(path, image, error);
  case image::NativeFormat::Exr: return image::readExr(path, image, error);
  case image::NativeFormat::Png: // read by OpenImageIO
  case image::NativeFormat::None: break;
  }
  return image::ReadResult::Unsupported;
}

} // namespace

bool readImage(const std::string &path, ImageData &image, std::string &error) {
  image::ReadResult result = readNative(path, image, error);
  if (result != image::ReadResult::Unsupported)
    return result == image::ReadResult::Read;
  return image::readWithOiio(path, image, error);
}

bool readImageNatively(const std::string &path, ImageData &image, std::string &error) {
  return readNative(path, image, error) == image::ReadResult::Read;
}

} // namespace osl
