//===- ImageOutput.cpp - Write/read shaded images with OpenImageIO ---------===//
//
// Compiled with -fexceptions in the OslImageIO library: OIIO's headers
// need exceptions, the LLVM-using runtime is built without them.
//
//===----------------------------------------------------------------------===//

#include "OslRuntime/ImageOutput.h"

#include <OpenImageIO/imageio.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace osl {

namespace {

/// An ImageOutput opened on `path` with testshade's spec for the image.
std::unique_ptr<OIIO::ImageOutput> openOutput(const std::string &path,
                                              const std::string &formatFrom, int xres,
                                              int yres, int channels,
                                              const std::string &dataType,
                                              bool integerPixels, std::string &error) {
  if (xres <= 0 || yres <= 0 || channels <= 0) {
    error = "cannot write an empty image to " + formatFrom;
    return nullptr;
  }
  auto out = OIIO::ImageOutput::create(formatFrom);
  if (!out) {
    error = "cannot write " + formatFrom + ": " + OIIO::geterror();
    return nullptr;
  }
  // Same spec as testshade's output ImageBuf; the names are set explicitly
  // because comparisons match channels by name (EXR sorts them).
  OIIO::TypeDesc type = OIIO::TypeDesc::FLOAT;
  if (!dataType.empty()) {
    type = OIIO::TypeDesc(dataType);
    if (type == OIIO::TypeDesc::UNKNOWN) {
      error = "unknown image data type '" + dataType + "'";
      return nullptr;
    }
  }
  if (integerPixels && dataType.empty())
    type = OIIO::TypeDesc::INT;
  OIIO::ImageSpec spec(xres, yres, channels, type);
  static const char *const kRGBA[] = {"R", "G", "B", "A"};
  for (int c = 0; c < channels; ++c)
    spec.channelnames[c] = channels == 1 ? std::string("Y")
                           : c < 4       ? std::string(kRGBA[c])
                                         : "channel" + std::to_string(c);
  if (!out->open(path, spec)) {
    error = "cannot write " + formatFrom + ": " + out->geterror();
    return nullptr;
  }
  return out;
}

/// testshade writes an int output's pixels as ints: stored as such in a
/// format with 32-bit ints (TIFF), converted by OIIO to -od's type (which
/// scales them as fractions of INT_MAX). Without -od, a format without ints
/// (EXR) stores the values as floats here, as the conformance corpus has them.
bool writesIntPixels(const std::string &formatFrom, const std::string &dataType) {
  if (!dataType.empty())
    return true;
  auto out = OIIO::ImageOutput::create(formatFrom);
  return out && std::string(out->format_name()) == "tiff";
}

/// The rows as OIIO reads them: floats, or the ints they hold exactly.
bool writeScanlines(OIIO::ImageOutput &out, int rowBegin, int rowEnd, size_t count,
                    const float *data, bool integerPixels) {
  if (!integerPixels)
    return out.write_scanlines(rowBegin, rowEnd, 0, OIIO::TypeDesc::FLOAT, data);
  std::vector<int32_t> ints(data, data + count);
  return out.write_scanlines(rowBegin, rowEnd, 0, OIIO::TypeDesc::INT, ints.data());
}

} // namespace

bool writeImage(const std::string &path, int xres, int yres, int channels,
                const float *data, std::string &error, const std::string &dataType,
                bool integerValues) {
  // testshade's `-o NAME null` shades the output but writes nothing.
  if (path == "null")
    return true;
  if (!data) {
    error = "cannot write an empty image to " + path;
    return false;
  }
  bool integerPixels = integerValues && writesIntPixels(path, dataType);
  auto out = openOutput(path, path, xres, yres, channels, dataType, integerPixels, error);
  if (!out)
    return false;
  if (!writeScanlines(*out, 0, yres, size_t(xres) * yres * channels, data, integerPixels)) {
    error = "cannot write " + path + ": " + out->geterror();
    out->close();
    return false;
  }
  if (!out->close()) {
    error = "cannot write " + path + ": " + out->geterror();
    return false;
  }
  return true;
}

struct ImageStream::Impl {
  std::unique_ptr<OIIO::ImageOutput> out;
  std::string path, temporary;
  int xres = 0, channels = 0;
  bool integerPixels = false;
};

ImageStream::ImageStream() = default;
ImageStream::ImageStream(ImageStream &&) noexcept = default;
ImageStream &ImageStream::operator=(ImageStream &&) noexcept = default;

ImageStream::~ImageStream() {
  if (impl && impl->out) {
    impl->out->close();
    std::remove(impl->temporary.c_str());
  }
}

bool ImageStream::open(const std::string &path, int xres, int yres, int channels,
                       std::string &error, const std::string &dataType,
                       bool integerValues) {
  impl = std::make_unique<Impl>();
  impl->path = path;
  // Same directory, so the rename is atomic; the format comes from `path`.
  impl->temporary = path + ".part";
  impl->xres = xres;
  impl->channels = channels;
  // One OpenEXR thread: it keeps compression buffers of 16 rows per
  // thread, about 35 MB per file for a 20000-wide image on a 2-core machine
  // (measured), which would defeat streaming. The output's own threads()
  // does not reach OpenEXR in OIIO 2.4, so this sets the process-wide
  // attribute: only grids too large for memory stream, and they are
  // bound by shading, not compression.
  OIIO::attribute("exr_threads", 1);
  impl->integerPixels = integerValues && writesIntPixels(path, dataType);
  impl->out = openOutput(impl->temporary, path, xres, yres, channels, dataType,
                         impl->integerPixels, error);
  return impl->out != nullptr;
}

bool ImageStream::writeRows(int rowBegin, int rowEnd, const float *data, std::string &error) {
  if (!impl || !impl->out) {
    error = "image stream is not open";
    return false;
  }
  if (!writeScanlines(*impl->out, rowBegin, rowEnd,
                      size_t(rowEnd - rowBegin) * impl->xres * impl->channels, data,
                      impl->integerPixels)) {
    error = "cannot write " + impl->path + ": " + impl->out->geterror();
    return false;
  }
  return true;
}

bool ImageStream::close(std::string &error) {
  if (!impl || !impl->out)
    return true;
  bool closed = impl->out->close();
  if (!closed)
    error = "cannot write " + impl->path + ": " + impl->out->geterror();
  impl->out.reset();
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
  return impl && impl->out ? impl->temporary.c_str() : nullptr;
}

bool readImage(const std::string &path, ImageData &image, std::string &error) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    error = "cannot read " + path + ": " + OIIO::geterror();
    return false;
  }
  const OIIO::ImageSpec &spec = in->spec();
  image.xres = spec.width;
  image.yres = spec.height;
  image.channels = spec.nchannels;
  image.channelNames = spec.channelnames;
  image.pixels.assign(static_cast<size_t>(spec.width) * spec.height *
                          spec.nchannels,
                      0.0f);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT,
                      image.pixels.data())) {
    error = "cannot read " + path + ": " + in->geterror();
    return false;
  }
  in->close();
  return true;
}

} // namespace osl
