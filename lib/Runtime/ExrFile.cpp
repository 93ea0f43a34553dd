//===- ExrFile.cpp - OpenEXR images through OpenEXR -----------------------===//
//
// Scanline EXR files of half or float channels, zip-compressed, written a
// band of rows at a time; reads any single-part, single-level EXR.
// OpenEXR reports errors with exceptions (this library is built with them).
//
//===----------------------------------------------------------------------===//
#include "ImageFormats.h"
#include "PixelConversion.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfTileDescriptionAttribute.h>

#include <algorithm>
#include <exception>

namespace osl::image {

namespace {

class ExrWriter : public Writer {
public:
  ExrWriter(std::unique_ptr<Imf::OutputFile> file, const WriteSpec &spec, PixelType type,
            std::string path)
      : file(std::move(file)), spec(spec), type(type), path(std::move(path)),
        names(channelNames(spec.channels)) {}

  bool writeRows(int rowBegin, int rowEnd, const float *data, std::string &error) override {
    size_t values = size_t(rowEnd - rowBegin) * spec.xres * spec.channels;
    data = floatValues(data, values, spec.intBits && !spec.integerPixels, ints);
    size_t bytes = pixelTypeBytes(type);
    const char *pixels = reinterpret_cast<const char *>(data);
    if (type != PixelType::Float || spec.integerPixels) {
      band.resize(values * bytes);
      convertPixels(data, values, spec.integerPixels, type, band.data());
      pixels = band.data();
    }
    // The slices address the band as if it held the whole image.
    size_t xStride = bytes * spec.channels, yStride = xStride * spec.xres;
    const char *origin = pixels - ptrdiff_t(rowBegin) * ptrdiff_t(yStride);
    Imf::PixelType exrType = type == PixelType::Half ? Imf::HALF : Imf::FLOAT;
    Imf::FrameBuffer frame;
    for (int c = 0; c < spec.channels; ++c)
      frame.insert(names[c], Imf::Slice(exrType, const_cast<char *>(origin + c * bytes),
                                        xStride, yStride));
    try {
      file->setFrameBuffer(frame);
      file->writePixels(rowEnd - rowBegin);
    } catch (const std::exception &e) {
      error = "cannot write " + path + ": " + e.what();
      return false;
    }
    return true;
  }

  bool close(std::string &error) override {
    try {
      file.reset(); // the destructor writes the offset table
    } catch (const std::exception &e) {
      error = "cannot write " + path + ": " + e.what();
      return false;
    }
    return true;
  }

private:
  std::unique_ptr<Imf::OutputFile> file;
  WriteSpec spec;
  PixelType type;
  std::string path;
  std::vector<std::string> names;
  std::vector<char> band;
  std::vector<float> ints; // an int output's values as floats
};

/// OpenImageIO's order for an EXR's channels: R, G, B, A first, the others
/// as the file lists them (sorted by name).
std::vector<std::string> readOrder(const Imf::ChannelList &list) {
  std::vector<std::string> names;
  for (auto it = list.begin(); it != list.end(); ++it)
    names.push_back(it.name());
  auto rank = [](const std::string &n) {
    static const char *const kFirst[] = {"R", "G", "B", "A"};
    for (int i = 0; i < 4; ++i)
      if (n == kFirst[i])
        return i;
    return 4;
  };
  std::stable_sort(names.begin(), names.end(),
                   [&](const std::string &a, const std::string &b) { return rank(a) < rank(b); });
  return names;
}

} // namespace

std::unique_ptr<Writer> openExr(const std::string &path, const WriteSpec &spec,
                                std::string &error) {
  // testshade's int outputs stay floats in an EXR unless -od names a type.
  WriteSpec stored = spec;
  stored.integerPixels = spec.integerPixels && !spec.dataType.empty();
  PixelType type = PixelType::Float;
  if (!spec.dataType.empty() &&
      (!pixelTypeNamed(spec.dataType, type) ||
       (type != PixelType::Half && type != PixelType::Float)))
    return nullptr;
  Imf::Header header(spec.xres, spec.yres);
  header.compression() = Imf::ZIP_COMPRESSION;
  std::vector<std::string> names = channelNames(spec.channels);
  for (const std::string &name : names)
    header.channels().insert(name, Imf::Channel(type == PixelType::Half ? Imf::HALF : Imf::FLOAT));
  try {
    auto file = std::make_unique<Imf::OutputFile>(path.c_str(), header);
    return std::make_unique<ExrWriter>(std::move(file), stored, type, path);
  } catch (const std::exception &e) {
    error = "cannot write " + path + ": " + e.what();
    return nullptr;
  }
}

ReadResult readExr(const std::string &path, ImageData &image, std::string &error) {
  try {
    if (Imf::MultiPartInputFile(path.c_str()).parts() != 1)
      return ReadResult::Unsupported;
    Imf::InputFile file(path.c_str());
    const Imf::Header &header = file.header();
    if (header.hasTileDescription() && header.tileDescription().mode != Imf::ONE_LEVEL)
      return ReadResult::Unsupported;
    const Imath::Box2i &window = header.dataWindow();
    int xres = window.max.x - window.min.x + 1, yres = window.max.y - window.min.y + 1;
    std::vector<std::string> names = readOrder(header.channels());
    if (xres <= 0 || yres <= 0 || names.empty())
      return ReadResult::Unsupported;
    image.xres = xres;
    image.yres = yres;
    image.channels = int(names.size());
    image.channelNames = names;
    image.pixels.assign(size_t(xres) * yres * names.size(), 0.0f);
    size_t xStride = sizeof(float) * names.size(), yStride = xStride * size_t(xres);
    char *origin = reinterpret_cast<char *>(image.pixels.data()) -
                   ptrdiff_t(window.min.x) * ptrdiff_t(xStride) -
                   ptrdiff_t(window.min.y) * ptrdiff_t(yStride);
    Imf::FrameBuffer frame;
    for (size_t c = 0; c < names.size(); ++c)
      frame.insert(names[c],
                   Imf::Slice(Imf::FLOAT, origin + c * sizeof(float), xStride, yStride));
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
  } catch (const std::exception &e) {
    error = "cannot read " + path + ": " + e.what();
    return ReadResult::Failed;
  }
  return ReadResult::Read;
}

} // namespace osl::image
