//===- ImageOutput.cpp - Write/read shaded images with OpenImageIO ---------===//
//
// Compiled with -fexceptions in the OslImageIO library: OIIO's headers
// need exceptions, the LLVM-using runtime is built without them.
//
//===----------------------------------------------------------------------===//

#include "OslRuntime/ImageOutput.h"

#include <OpenImageIO/imageio.h>

namespace osl {

bool writeImage(const std::string &path, int xres, int yres, int channels,
                const float *data, std::string &error, const std::string &dataType) {
  // testshade's `-o NAME null` shades the output but writes nothing.
  if (path == "null")
    return true;
  if (xres <= 0 || yres <= 0 || channels <= 0 || !data) {
    error = "cannot write an empty image to " + path;
    return false;
  }
  auto out = OIIO::ImageOutput::create(path);
  if (!out) {
    error = "cannot write " + path + ": " + OIIO::geterror();
    return false;
  }
  // Same spec as testshade's output ImageBuf; the names are set explicitly
  // because comparisons match channels by name (EXR sorts them).
  OIIO::TypeDesc type = OIIO::TypeDesc::FLOAT;
  if (!dataType.empty()) {
    type = OIIO::TypeDesc(dataType);
    if (type == OIIO::TypeDesc::UNKNOWN) {
      error = "unknown image data type '" + dataType + "'";
      return false;
    }
  }
  OIIO::ImageSpec spec(xres, yres, channels, type);
  static const char *const kRGBA[] = {"R", "G", "B", "A"};
  for (int c = 0; c < channels; ++c)
    spec.channelnames[c] = channels == 1 ? std::string("Y")
                           : c < 4       ? std::string(kRGBA[c])
                                         : "channel" + std::to_string(c);
  if (!out->open(path, spec)) {
    error = "cannot write " + path + ": " + out->geterror();
    return false;
  }
  if (!out->write_image(OIIO::TypeDesc::FLOAT, data)) {
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
