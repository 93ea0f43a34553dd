//===- NativeImageFilesTest.cpp - TIFF/EXR as OpenImageIO writes them -----===//
//
// The native writers (libtiff, OpenEXR) took over from OpenImageIO for the
// formats testshade writes; every stored value must be what OpenImageIO
// (in its module) stores for the same floats and spec: rounding at exact
// halves, clamping, negative and huge values, whole numbers as ints.
//
//===----------------------------------------------------------------------===//
#include "ImageFormats.h"
#include "OslRuntime/ImageOutput.h"

#include "gtest/gtest.h"

#include <png.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <unistd.h>

using namespace osl;

namespace {

float bitsAsFloat(int32_t value) {
  float bits;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

std::string tempPath(const std::string &name) {
  const char *dir = std::getenv("TMPDIR");
  return std::string(dir ? dir : "/tmp") + "/osl_native_image_" + std::to_string(getpid()) +
         "_" + name;
}

/// Values where conversions differ if done differently: exact halves of
/// 8- and 16-bit steps, out of range, negative, tiny, huge, infinite; as
/// ints, an int output's bits (Grid.h), also past a float's 2^24.
std::vector<float> trickyValues(size_t count, bool ints) {
  std::vector<float> pool;
  if (ints) {
    for (int32_t value : {0, 1, -1, 7, 255, 256, -300, 65535, 65536, 16777217, -16777219,
                          2147483647, -2147483647 - 1, 12345})
      pool.push_back(bitsAsFloat(value));
  } else {
    for (int k = 0; k < 8; ++k) {
      pool.push_back((2 * k + 0.5f) / 255.0f);
      pool.push_back((2 * k + 1.5f) / 255.0f);
      pool.push_back((2 * k + 0.5f) / 65535.0f);
    }
    pool.insert(pool.end(), {0.0f, -0.0f, 1.0f, -0.25f, 1.5f, 1e-30f, 3e38f, -3e38f,
                             0.123456789f, std::numeric_limits<float>::infinity(),
                             -std::numeric_limits<float>::infinity()});
  }
  std::vector<float> values(count);
  for (size_t i = 0; i < count; ++i)
    values[i] = pool[(i * 7 + i / pool.size()) % pool.size()];
  return values;
}

bool write(std::unique_ptr<image::Writer> writer, const image::WriteSpec &spec,
           const std::vector<float> &data, std::string &error) {
  return writer && writer->writeRows(0, spec.yres, data.data(), error) && writer->close(error);
}

/// An image of `shape` (width, height, channels) stored as `type`.
image::WriteSpec specOf(const int shape[3], const std::string &type, bool integerPixels) {
  image::WriteSpec spec;
  spec.xres = shape[0];
  spec.yres = shape[1];
  spec.channels = shape[2];
  spec.dataType = type;
  spec.intBits = integerPixels;
  spec.integerPixels = integerPixels;
  return spec;
}

std::string describe(const image::WriteSpec &spec) {
  return " type '" + spec.dataType + "'" + (spec.integerPixels ? " ints " : " ") +
         std::to_string(spec.xres) + "x" + std::to_string(spec.yres) + "x" +
         std::to_string(spec.channels);
}

/// A PNG's header fields and samples as stored (16-bit ones in host
/// order), with no alpha conversion: false when libpng cannot read it.
struct StoredPng {
  png_uint_32 width = 0, height = 0;
  int bitDepth = 0, colorType = 0;
  std::vector<unsigned char> samples;
};

bool readStoredPng(const std::string &path, StoredPng &stored) {
  std::FILE *file = std::fopen(path.c_str(), "rb");
  if (!file)
    return false;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  std::vector<png_bytep> rows;
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    std::fclose(file);
    return false;
  }
  png_init_io(png, file);
  png_read_info(png, info);
  stored.width = png_get_image_width(png, info);
  stored.height = png_get_image_height(png, info);
  stored.bitDepth = png_get_bit_depth(png, info);
  stored.colorType = png_get_color_type(png, info);
  if (stored.bitDepth == 16)
    png_set_swap(png);
  size_t rowBytes = png_get_rowbytes(png, info);
  stored.samples.assign(rowBytes * stored.height, 0);
  rows.resize(stored.height);
  for (png_uint_32 y = 0; y < stored.height; ++y)
    rows[y] = stored.samples.data() + y * rowBytes;
  png_read_image(png, rows.data());
  png_destroy_read_struct(&png, &info, nullptr);
  std::fclose(file);
  return true;
}

} // namespace

TEST(NativeImageFiles, StoreWhatOpenImageIOStores) {
  const std::string types[] = {"", "uint8", "uint16", "half", "float"};
  const int shapes[][3] = {{1, 1, 1}, {1, 1, 3}, {3, 1, 3}, {5, 3, 4}, {7, 2, 5}, {2, 2, 2}};
  int compared = 0;
  for (const char *extension : {".tif", ".exr"}) {
    for (const std::string &type : types) {
      for (bool ints : {false, true}) {
        for (const auto &shape : shapes) {
          image::WriteSpec spec = specOf(shape, type, ints);
          SCOPED_TRACE(extension + describe(spec));
          std::vector<float> data = trickyValues(size_t(shape[0]) * shape[1] * shape[2], ints);
          std::string nativePath = tempPath("native") + extension;
          std::string oiioPath = tempPath("oiio") + extension;
          std::string error;
          std::unique_ptr<image::Writer> native =
              extension == std::string(".tif") ? image::openTiff(nativePath, spec, error)
                                               : image::openExr(nativePath, spec, error);
          if (!native && error.empty())
            continue; // a spec left to OpenImageIO
          ASSERT_TRUE(write(std::move(native), spec, data, error)) << error;
          ASSERT_TRUE(write(image::openWithOiio(oiioPath, oiioPath, spec, error), spec, data,
                            error))
              << error;
          ImageData ours, theirs;
          ASSERT_TRUE(readImageNatively(nativePath, ours, error)) << error;
          ASSERT_TRUE(readImageNatively(oiioPath, theirs, error)) << error;
          EXPECT_EQ(ours.channelNames, theirs.channelNames);
          ASSERT_EQ(ours.pixels.size(), theirs.pixels.size());
          for (size_t i = 0; i < ours.pixels.size(); ++i)
            EXPECT_EQ(0, std::memcmp(&ours.pixels[i], &theirs.pixels[i], sizeof(float)))
                << "value " << i << " (" << data[i] << "): " << ours.pixels[i] << " vs "
                << theirs.pixels[i];
          ++compared;
          std::remove(nativePath.c_str());
          std::remove(oiioPath.c_str());
        }
      }
    }
  }
  // TIFF: 5 types x 2 x 6 shapes; EXR: 3 types (float, half, none) x 2 x 6.
  EXPECT_EQ(compared, 60 + 36);
}

TEST(NativeImageFiles, PngStoresWhatOpenImageIOStores) {
  // Compared as stored: OpenImageIO's reader would multiply by alpha again,
  // hiding what a zero alpha leaves in the colors.
  const std::string types[] = {"", "uint8", "uint16", "half", "float"};
  const int shapes[][3] = {{1, 1, 1}, {3, 1, 2}, {3, 2, 3}, {5, 3, 4}, {40, 7, 4}, {2, 2, 2}};
  int compared = 0;
  for (const std::string &type : types) {
    for (bool ints : {false, true}) {
      for (const auto &shape : shapes) {
        // (Without -od, both store an int output's whole numbers as floats.)
        image::WriteSpec spec = specOf(shape, type, ints);
        SCOPED_TRACE(describe(spec));
        std::vector<float> data = trickyValues(size_t(shape[0]) * shape[1] * shape[2], ints);
        std::string nativePath = tempPath("native.png"), oiioPath = tempPath("oiio.png");
        std::string error;
        ASSERT_TRUE(write(image::openPng(nativePath, spec, error), spec, data, error)) << error;
        ASSERT_TRUE(write(image::openWithOiio(oiioPath, oiioPath, spec, error), spec, data,
                          error))
            << error;
        StoredPng ours, theirs;
        ASSERT_TRUE(readStoredPng(nativePath, ours));
        ASSERT_TRUE(readStoredPng(oiioPath, theirs));
        EXPECT_EQ(ours.width, theirs.width);
        EXPECT_EQ(ours.height, theirs.height);
        EXPECT_EQ(ours.bitDepth, theirs.bitDepth);
        EXPECT_EQ(ours.colorType, theirs.colorType);
        EXPECT_EQ(ours.samples, theirs.samples);
        ++compared;
        std::remove(nativePath.c_str());
        std::remove(oiioPath.c_str());
      }
    }
  }
  EXPECT_EQ(compared, 5 * 2 * 6);
}

TEST(NativeImageFiles, PngLeavesWideOutputsToOpenImageIO) {
  image::WriteSpec spec;
  spec.xres = spec.yres = 2;
  spec.channels = 5;
  std::string error;
  EXPECT_EQ(image::openPng(tempPath("wide.png"), spec, error), nullptr);
  EXPECT_TRUE(error.empty()) << error;
}

TEST(NativeImageFiles, PngWriteFailureIsAnError) {
  image::WriteSpec spec;
  spec.xres = spec.yres = 2;
  spec.channels = 3;
  std::string error;
  EXPECT_EQ(image::openPng("/nonexistent-dir/x.png", spec, error), nullptr);
  EXPECT_NE(error.find("cannot write /nonexistent-dir/x.png"), std::string::npos) << error;
}

TEST(NativeImageFiles, ReadBackWhatOpenImageIOReads) {
  image::WriteSpec spec;
  spec.xres = 9;
  spec.yres = 4;
  spec.channels = 3;
  spec.dataType = "uint16";
  std::vector<float> data = trickyValues(9 * 4 * 3, false);
  std::string path = tempPath("read.tif"), error;
  ASSERT_TRUE(write(image::openWithOiio(path, path, spec, error), spec, data, error)) << error;
  ImageData ours, theirs;
  ASSERT_TRUE(readImageNatively(path, ours, error)) << error;
  ASSERT_TRUE(image::readWithOiio(path, theirs, error)) << error;
  EXPECT_EQ(ours.xres, theirs.xres);
  EXPECT_EQ(ours.channels, theirs.channels);
  EXPECT_EQ(ours.pixels, theirs.pixels);
  std::remove(path.c_str());
}

TEST(NativeImageFiles, OtherLayoutsAreLeftToOpenImageIO) {
  // A PNG is written natively but read by OpenImageIO: readImageNatively
  // declines without an error.
  std::vector<float> pixel = {0.5f, 0.25f, 1.0f};
  std::string path = tempPath("x.png"), error;
  ASSERT_TRUE(writeImage(path, 1, 1, 3, pixel.data(), error)) << error;
  ImageData image;
  EXPECT_FALSE(readImageNatively(path, image, error));
  EXPECT_TRUE(error.empty()) << error;
  EXPECT_TRUE(readImage(path, image, error)) << error;
  std::remove(path.c_str());
}
