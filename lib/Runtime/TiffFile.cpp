//===- TiffFile.cpp - TIFF images through libtiff -------------------------===//
//
// The TIFF files testshade writes (8/16-bit unsigned, half, float, 32-bit
// int pixels; contiguous samples, deflate) and reads back the same layouts.
// Values are converted with OpenImageIO's inline conversions (fmath.h).
//
//===----------------------------------------------------------------------===//
#include "ImageFormats.h"
#include "PixelConversion.h"

#include <tiffio.h>

#include <cstdarg>
#include <cstdio>
#include <cstring>

namespace osl::image {

namespace {

/// libtiff reports through handlers; the first message of a file is kept.
int keepTiffError(TIFF *, void *user, const char *, const char *fmt, va_list ap) {
  auto *messages = static_cast<std::string *>(user);
  if (messages->empty()) {
    char text[512];
    std::vsnprintf(text, sizeof text, fmt, ap);
    *messages = text;
  }
  return 1;
}

int ignoreTiffWarning(TIFF *, void *, const char *, const char *, va_list) { return 1; }

/// Opens `path` with libtiff's messages going to `messages`.
TIFF *openTiffFile(const std::string &path, const char *mode, std::string *messages) {
  TIFFOpenOptions *options = TIFFOpenOptionsAlloc();
  TIFFOpenOptionsSetErrorHandlerExtR(options, keepTiffError, messages);
  TIFFOpenOptionsSetWarningHandlerExtR(options, ignoreTiffWarning, nullptr);
  TIFF *tif = TIFFOpenExt(path.c_str(), mode, options);
  TIFFOpenOptionsFree(options);
  return tif;
}

class TiffWriter : public Writer {
public:
  TiffWriter(TIFF *tif, const WriteSpec &spec, PixelType type, std::string path,
             std::unique_ptr<std::string> messages)
      : tif(tif), spec(spec), type(type), path(std::move(path)), messages(std::move(messages)),
        row(size_t(spec.xres) * spec.channels * pixelTypeBytes(type)) {}
  ~TiffWriter() override {
    if (tif)
      TIFFClose(tif);
  }

  bool writeRows(int rowBegin, int rowEnd, const float *data, std::string &error) override {
    size_t values = size_t(spec.xres) * spec.channels;
    for (int y = rowBegin; y < rowEnd; ++y) {
      convertPixels(data + size_t(y - rowBegin) * values, values, spec.integerPixels, type,
                    row.data());
      if (TIFFWriteScanline(tif, row.data(), uint32_t(y), 0) < 0)
        return fail(error);
    }
    return true;
  }

  bool close(std::string &error) override {
    if (!tif)
      return true;
    bool flushed = TIFFFlush(tif) == 1;
    TIFFClose(tif);
    tif = nullptr;
    return flushed || fail(error);
  }

private:
  bool fail(std::string &error) {
    error = "cannot write " + path + (messages->empty() ? "" : ": " + *messages);
    return false;
  }

  TIFF *tif;
  WriteSpec spec;
  PixelType type;
  std::string path;
  std::unique_ptr<std::string> messages;
  std::vector<unsigned char> row;
};

/// testshade's stored type for a TIFF, or false where OpenImageIO decides.
bool tiffPixelType(const WriteSpec &spec, PixelType &type) {
  if (spec.dataType.empty()) {
    type = spec.integerPixels ? PixelType::Int32 : PixelType::Float;
    return true;
  }
  if (!pixelTypeNamed(spec.dataType, type))
    return false;
  // OpenImageIO's TIFF writer stores half as float.
  if (type == PixelType::Half)
    type = PixelType::Float;
  return true;
}

} // namespace

std::unique_ptr<Writer> openTiff(const std::string &path, const WriteSpec &spec,
                                 std::string &error) {
  PixelType type;
  if (!tiffPixelType(spec, type))
    return nullptr;
  auto messages = std::make_unique<std::string>();
  TIFF *tif = openTiffFile(path, "w", messages.get());
  if (!tif) {
    error = "cannot write " + path + (messages->empty() ? "" : ": " + *messages);
    return nullptr;
  }
  uint16_t bits = uint16_t(pixelTypeBytes(type) * 8);
  uint16_t format = type == PixelType::Int32 ? SAMPLEFORMAT_INT
                    : type == PixelType::Half || type == PixelType::Float
                        ? SAMPLEFORMAT_IEEEFP
                        : SAMPLEFORMAT_UINT;
  TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, uint32_t(spec.xres));
  TIFFSetField(tif, TIFFTAG_IMAGELENGTH, uint32_t(spec.yres));
  TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, uint16_t(spec.channels));
  TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, bits);
  TIFFSetField(tif, TIFFTAG_SAMPLEFORMAT, format);
  TIFFSetField(tif, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
  TIFFSetField(tif, TIFFTAG_ORIENTATION, ORIENTATION_TOPLEFT);
  TIFFSetField(tif, TIFFTAG_COMPRESSION, COMPRESSION_ADOBE_DEFLATE);
  TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, uint32_t(32));
  int colorChannels = spec.channels >= 3 ? 3 : 1;
  TIFFSetField(tif, TIFFTAG_PHOTOMETRIC,
               colorChannels == 3 ? PHOTOMETRIC_RGB : PHOTOMETRIC_MINISBLACK);
  // Channels past the color ones: the fourth, named A, is alpha.
  std::vector<uint16_t> extra(size_t(spec.channels - colorChannels), EXTRASAMPLE_UNSPECIFIED);
  if (spec.channels >= 4)
    extra[0] = EXTRASAMPLE_ASSOCALPHA;
  if (!extra.empty())
    TIFFSetField(tif, TIFFTAG_EXTRASAMPLES, uint16_t(extra.size()), extra.data());
  return std::make_unique<TiffWriter>(tif, spec, type, path, std::move(messages));
}

ReadResult readTiff(const std::string &path, ImageData &image, std::string &error) {
  std::string messages;
  TIFF *tif = openTiffFile(path, "r", &messages);
  if (!tif) {
    error = "cannot read " + path + (messages.empty() ? "" : ": " + messages);
    return ReadResult::Failed;
  }
  struct Closer {
    TIFF *tif;
    ~Closer() { TIFFClose(tif); }
  } closer{tif};
  uint32_t width = 0, height = 0;
  uint16_t channels = 1, bits = 1, format = SAMPLEFORMAT_UINT, planar = PLANARCONFIG_CONTIG,
           photometric = PHOTOMETRIC_MINISBLACK, orientation = ORIENTATION_TOPLEFT;
  TIFFGetField(tif, TIFFTAG_IMAGEWIDTH, &width);
  TIFFGetField(tif, TIFFTAG_IMAGELENGTH, &height);
  TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLESPERPIXEL, &channels);
  TIFFGetFieldDefaulted(tif, TIFFTAG_BITSPERSAMPLE, &bits);
  TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLEFORMAT, &format);
  TIFFGetFieldDefaulted(tif, TIFFTAG_PLANARCONFIG, &planar);
  TIFFGetField(tif, TIFFTAG_PHOTOMETRIC, &photometric);
  TIFFGetFieldDefaulted(tif, TIFFTAG_ORIENTATION, &orientation);
  PixelType type;
  bool known = bits == 8 && format == SAMPLEFORMAT_UINT   ? (type = PixelType::UInt8, true)
               : bits == 16 && format == SAMPLEFORMAT_UINT ? (type = PixelType::UInt16, true)
               : bits == 16 && format == SAMPLEFORMAT_IEEEFP ? (type = PixelType::Half, true)
               : bits == 32 && format == SAMPLEFORMAT_IEEEFP ? (type = PixelType::Float, true)
               : bits == 32 && format == SAMPLEFORMAT_INT    ? (type = PixelType::Int32, true)
                                                              : false;
  bool plainLayout = !TIFFIsTiled(tif) && orientation == ORIENTATION_TOPLEFT &&
                     (photometric == PHOTOMETRIC_MINISBLACK || photometric == PHOTOMETRIC_RGB) &&
                     TIFFNumberOfDirectories(tif) == 1 && width > 0 && height > 0;
  if (!known || !plainLayout)
    return ReadResult::Unsupported;
  image.xres = int(width);
  image.yres = int(height);
  image.channels = channels;
  image.channelNames = channels == 1 ? std::vector<std::string>{"Y"} : channelNames(channels);
  size_t values = size_t(width) * channels;
  image.pixels.assign(values * height, 0.0f);
  std::vector<unsigned char> row(size_t(TIFFScanlineSize64(tif)));
  std::vector<unsigned char> samples(values * pixelTypeBytes(type));
  size_t bytes = pixelTypeBytes(type);
  for (uint32_t y = 0; y < height; ++y) {
    if (planar == PLANARCONFIG_CONTIG) {
      if (TIFFReadScanline(tif, samples.data(), y, 0) < 0)
        break;
    } else {
      // One plane per channel: interleave them.
      for (uint16_t c = 0; c < channels; ++c) {
        if (TIFFReadScanline(tif, row.data(), y, c) < 0)
          break;
        for (uint32_t x = 0; x < width; ++x)
          std::memcpy(&samples[(size_t(x) * channels + c) * bytes], &row[x * bytes], bytes);
      }
    }
    if (!messages.empty())
      break;
    convertToFloat(samples.data(), type, values, image.pixels.data() + y * values);
  }
  if (!messages.empty()) {
    error = "cannot read " + path + ": " + messages;
    return ReadResult::Failed;
  }
  return ReadResult::Read;
}

} // namespace osl::image
