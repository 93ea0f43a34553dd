//===- PngFile.cpp - PNG images through libpng ----------------------------===//
//
// osl-run's default output is <shader>.png; through OpenImageIO's module
// that first write cost ~0.27 s of dynamic loading, 30 times the compile of
// a small shader. This writer stores what OpenImageIO 2.4's PNG writer
// stores for the same floats: 16-bit samples for -od uint16, 8-bit for
// everything else, and colors divided by alpha (PNG's alpha is
// unassociated) in the stored integers, truncating.
//
//===----------------------------------------------------------------------===//
#include "ImageFormats.h"
#include "PixelConversion.h"

#include <png.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <limits>

namespace osl::image {

namespace {

/// libpng reports errors by longjmp; the message is kept for the caller.
void keepPngError(png_structp png, png_const_charp message) {
  auto *kept = static_cast<std::string *>(png_get_error_ptr(png));
  if (kept->empty())
    *kept = message;
  png_longjmp(png, 1);
}

void ignorePngWarning(png_structp, png_const_charp) {}

/// Colors divided by alpha in place, in the stored integers and truncated,
/// as OpenImageIO converts associated alpha for PNG.
template <typename T>
void unassociateAlpha(T *pixels, size_t count, int channels, int alphaChannel) {
  const unsigned max = std::numeric_limits<T>::max();
  for (size_t p = 0; p < count; ++p, pixels += channels) {
    unsigned alpha = pixels[alphaChannel];
    if (alpha == 0)
      continue;
    for (int c = 0; c < channels; ++c)
      if (c != alphaChannel)
        pixels[c] = T(std::min(max, unsigned(pixels[c]) * max / alpha));
  }
}

class PngWriter : public Writer {
public:
  PngWriter(std::FILE *file, const WriteSpec &spec, PixelType type, std::string path)
      : file(file), spec(spec), type(type), path(std::move(path)),
        row(size_t(spec.xres) * spec.channels * pixelTypeBytes(type)) {}
  ~PngWriter() override { release(); }

  /// Writes the header; false with `error` set when libpng refuses it.
  bool begin(std::string &error) {
    png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &messages, keepPngError,
                                  ignorePngWarning);
    info = png ? png_create_info_struct(png) : nullptr;
    if (!png || !info)
      return fail(error);
    if (setjmp(png_jmpbuf(png)))
      return fail(error);
    png_init_io(png, file);
    static const int kColorTypes[] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA,
                                      PNG_COLOR_TYPE_RGB, PNG_COLOR_TYPE_RGB_ALPHA};
    png_set_IHDR(png, info, png_uint_32(spec.xres), png_uint_32(spec.yres),
                 type == PixelType::UInt16 ? 16 : 8, kColorTypes[spec.channels - 1],
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_oFFs(png, info, 0, 0, PNG_OFFSET_PIXEL);
    png_write_info(png, info);
    // PNG's 16-bit samples are big-endian.
    if (type == PixelType::UInt16)
      png_set_swap(png);
    return true;
  }

  bool writeRows(int rowBegin, int rowEnd, const float *data, std::string &error) override {
    size_t values = size_t(spec.xres) * spec.channels;
    data = floatValues(data, values * size_t(rowEnd - rowBegin),
                       spec.intBits && !spec.integerPixels, ints);
    for (int y = rowBegin; y < rowEnd; ++y) {
      convertPixels(data + size_t(y - rowBegin) * values, values, spec.integerPixels, type,
                    row.data());
      if (spec.channels == 2 || spec.channels == 4) {
        if (type == PixelType::UInt16)
          unassociateAlpha(reinterpret_cast<uint16_t *>(row.data()), size_t(spec.xres),
                           spec.channels, spec.channels - 1);
        else
          unassociateAlpha(row.data(), size_t(spec.xres), spec.channels, spec.channels - 1);
      }
      if (!writeRow(row.data()))
        return fail(error);
    }
    return true;
  }

  bool close(std::string &error) override {
    if (!file)
      return true;
    bool ended = endImage();
    bool written = std::ferror(file) == 0;
    // The last buffer reaches the disk in fclose: a full disk shows there.
    bool closed = release();
    return (ended && written && closed) || fail(error);
  }

private:
  /// Each libpng call that can fail in a frame of its own: longjmp must
  /// not cross C++ objects with destructors.
  bool writeRow(unsigned char *bytes) {
    if (setjmp(png_jmpbuf(png)))
      return false;
    png_write_row(png, bytes);
    return true;
  }

  bool endImage() {
    if (setjmp(png_jmpbuf(png)))
      return false;
    png_write_end(png, nullptr);
    return true;
  }

  /// Frees libpng's state and closes the file; false when closing failed.
  bool release() {
    if (png)
      png_destroy_write_struct(&png, info ? &info : nullptr);
    png = nullptr;
    info = nullptr;
    bool closed = true;
    if (file && std::fclose(file) != 0) {
      closed = false;
      if (messages.empty())
        messages = std::strerror(errno);
    }
    file = nullptr;
    return closed;
  }

  bool fail(std::string &error) {
    error = "cannot write " + path + (messages.empty() ? "" : ": " + messages);
    return false;
  }

  std::FILE *file;
  WriteSpec spec;
  PixelType type;
  std::string path;
  std::string messages;
  png_structp png = nullptr;
  png_infop info = nullptr;
  std::vector<unsigned char> row;
  std::vector<float> ints; // an int output's values as floats
};

} // namespace

std::unique_ptr<Writer> openPng(const std::string &path, const WriteSpec &spec,
                                std::string &error) {
  // PNG holds gray, gray+alpha, RGB and RGBA; wider outputs are left to
  // OpenImageIO, which reports them.
  if (spec.channels < 1 || spec.channels > 4)
    return nullptr;
  PixelType type = PixelType::UInt8;
  if (spec.dataType == "uint16")
    type = PixelType::UInt16;
  // testshade's int outputs are floats in a PNG unless -od names a type
  // (as OpenImageIO's path writes them; see writesIntPixels).
  WriteSpec stored = spec;
  stored.integerPixels = spec.integerPixels && !spec.dataType.empty();
  std::FILE *file = std::fopen(path.c_str(), "wb");
  if (!file) {
    error = "cannot write " + path + ": " + std::strerror(errno);
    return nullptr;
  }
  auto writer = std::make_unique<PngWriter>(file, stored, type, path);
  if (!writer->begin(error))
    return nullptr;
  return writer;
}

} // namespace osl::image
