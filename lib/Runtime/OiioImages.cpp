//===- OiioImages.cpp - Images in any format OpenImageIO knows ------------===//
//
// Part of the OpenImageIO module (OiioModule.h): the formats and stored
// types the native TIFF and EXR code leaves to OpenImageIO.
//
//===----------------------------------------------------------------------===//
#include "OiioModuleParts.h"
#include "OslRuntime/Grid.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>


namespace osl::oiio {

namespace {

/// An image being written.
struct OpenImage {
  std::unique_ptr<OIIO::ImageOutput> out;
  std::string path;
  int xres = 0, channels = 0;
  bool integerValues = false; // the floats are an int output's bits (Grid.h)
  bool integerPixels = false; // written as ints
  bool displayConvert = false; // colorconvert linear -> sRGB first
};

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

} // namespace

void *openImage(const std::string &path, const std::string &formatFrom, int xres, int yres,
                int channels, const std::string &dataType, bool integerValues,
                bool displayConvert, std::string &error) {
  // One OpenEXR thread: it keeps compression buffers of 16 rows per
  // thread, which would defeat streaming huge grids. The output's own
  // threads() does not reach OpenEXR in OIIO 2.4, hence the global.
  OIIO::attribute("exr_threads", 1);
  auto out = OIIO::ImageOutput::create(formatFrom);
  if (!out) {
    error = "cannot write " + formatFrom + ": " + OIIO::geterror();
    return nullptr;
  }
  bool integerPixels = integerValues && writesIntPixels(formatFrom, dataType);
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
  // Set explicitly: comparisons match channels by name (EXR sorts them).
  static const char *const kRGBA[] = {"R", "G", "B", "A"};
  for (int c = 0; c < channels; ++c)
    spec.channelnames[c] = channels == 1 ? std::string("Y")
                           : c < 4       ? std::string(kRGBA[c])
                                         : "channel" + std::to_string(c);
  if (!out->open(path, spec)) {
    error = "cannot write " + formatFrom + ": " + out->geterror();
    return nullptr;
  }
  return new OpenImage{std::move(out), formatFrom, xres,          channels,
                       integerValues,  integerPixels, displayConvert};
}

bool writeRows(void *handle, int rowBegin, int rowEnd, const float *data, std::string &error) {
  auto &image = *static_cast<OpenImage *>(handle);
  bool ok;
  size_t count = size_t(rowEnd - rowBegin) * image.xres * image.channels;
  if (image.displayConvert) {
    // testshade's display image: its ImageBuf (an ImageSpec's default alpha
    // channel) through colorconvert, colors divided by alpha and back. (The
    // host gives an int output's values as floats.)
    std::vector<float> values(data, data + count);
    OIIO::ImageSpec band(image.xres, rowEnd - rowBegin, image.channels, OIIO::TypeDesc::FLOAT);
    OIIO::ImageBuf linear(band, values.data()), encoded;
    if (!OIIO::ImageBufAlgo::colorconvert(encoded, linear, "linear", "sRGB", true)) {
      error = "cannot write " + image.path + ": " + encoded.geterror();
      return false;
    }
    ok = image.out->write_scanlines(rowBegin, rowEnd, 0, OIIO::TypeDesc::FLOAT,
                                    encoded.localpixels());
  } else if (!image.integerValues) {
    ok = image.out->write_scanlines(rowBegin, rowEnd, 0, OIIO::TypeDesc::FLOAT, data);
  } else if (image.integerPixels) {
    // The ints' own bits.
    ok = image.out->write_scanlines(rowBegin, rowEnd, 0, OIIO::TypeDesc::INT, data);
  } else {
    std::vector<float> values(count);
    for (size_t i = 0; i < count; ++i)
      values[i] = float(intOutputValue(data[i]));
    ok = image.out->write_scanlines(rowBegin, rowEnd, 0, OIIO::TypeDesc::FLOAT, values.data());
  }
  if (!ok)
    error = "cannot write " + image.path + ": " + image.out->geterror();
  return ok;
}

bool closeImage(void *handle, std::string &error) {
  std::unique_ptr<OpenImage> image(static_cast<OpenImage *>(handle));
  if (image->out->close())
    return true;
  error = "cannot write " + image->path + ": " + image->out->geterror();
  return false;
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
  image.pixels.assign(size_t(spec.width) * spec.height * spec.nchannels, 0.0f);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data())) {
    error = "cannot read " + path + ": " + in->geterror();
    return false;
  }
  in->close();
  return true;
}

} // namespace osl::oiio
