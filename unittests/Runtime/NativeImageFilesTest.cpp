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

#include <cmath>
#include <cstring>
#include <limits>
#include <unistd.h>

using namespace osl;

namespace {

std::string tempPath(const std::string &name) {
  const char *dir = std::getenv("TMPDIR");
  return std::string(dir ? dir : "/tmp") + "/osl_native_image_" + std::to_string(getpid()) +
         "_" + name;
}

/// Values where conversions differ if done differently: exact halves of
/// 8- and 16-bit steps, out of range, negative, tiny, huge, infinite.
std::vector<float> trickyValues(size_t count, bool wholeNumbers) {
  std::vector<float> pool;
  if (wholeNumbers) {
    pool = {0, 1, -1, 7, 255, 256, -300, 65535, 65536, 2147483520.0f, -2147483648.0f, 12345};
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

} // namespace

TEST(NativeImageFiles, StoreWhatOpenImageIOStores) {
  const std::string types[] = {"", "uint8", "uint16", "half", "float"};
  const int shapes[][3] = {{1, 1, 1}, {1, 1, 3}, {3, 1, 3}, {5, 3, 4}, {7, 2, 5}, {2, 2, 2}};
  int compared = 0;
  for (const char *extension : {".tif", ".exr"}) {
    for (const std::string &type : types) {
      for (bool ints : {false, true}) {
        for (const auto &shape : shapes) {
          image::WriteSpec spec;
          spec.xres = shape[0];
          spec.yres = shape[1];
          spec.channels = shape[2];
          spec.dataType = type;
          spec.integerPixels = ints;
          SCOPED_TRACE(std::string(extension) + " type '" + type + "'" + (ints ? " ints" : "") +
                       " " + std::to_string(shape[0]) + "x" + std::to_string(shape[1]) + "x" +
                       std::to_string(shape[2]));
          std::vector<float> data =
              trickyValues(size_t(shape[0]) * shape[1] * shape[2], ints);
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
  // A PNG is no native format: readImageNatively declines without an error.
  std::vector<float> pixel = {0.5f, 0.25f, 1.0f};
  std::string path = tempPath("x.png"), error;
  ASSERT_TRUE(writeImage(path, 1, 1, 3, pixel.data(), error)) << error;
  ImageData image;
  EXPECT_FALSE(readImageNatively(path, image, error));
  EXPECT_TRUE(error.empty()) << error;
  EXPECT_TRUE(readImage(path, image, error)) << error;
  std::remove(path.c_str());
}
