//===- ImageOutputTest.cpp - Images as testshade writes them ---------------===//

#include "OslRuntime/ImageOutput.h"

#include "gtest/gtest.h"

#include <cstdio>
#include <string>
#include <unistd.h>
#include <vector>

using namespace osl;

namespace {

std::string tempPath(const std::string &name) {
  const char *dir = std::getenv("TMPDIR");
  return std::string(dir ? dir : "/tmp") + "/osl_runtime_test_" +
         std::to_string(getpid()) + "_" + name;
}

std::vector<float> ramp(int xres, int yres, int channels) {
  std::vector<float> data(size_t(xres) * yres * channels);
  for (size_t i = 0; i < data.size(); ++i)
    data[i] = float(i % 97) / 97.0f - 0.25f; // negative values survive EXR
  return data;
}

/// Index of channel `name` in `image`, or -1.
int channelIndex(const ImageData &image, const std::string &name) {
  for (size_t c = 0; c < image.channelNames.size(); ++c)
    if (image.channelNames[c] == name)
      return int(c);
  return -1;
}

} // namespace

TEST(ImageOutput, ExrRoundTripsFloatsWithTestshadeChannelNames) {
  struct Case {
    int channels;
    std::vector<std::string> names;
  } cases[] = {{1, {"Y"}},
               {3, {"R", "G", "B"}},
               {4, {"R", "G", "B", "A"}},
               {6, {"R", "G", "B", "A", "channel4", "channel5"}}};
  for (const Case &c : cases) {
    SCOPED_TRACE(c.channels);
    std::string path = tempPath(std::to_string(c.channels) + ".exr");
    std::vector<float> data = ramp(7, 5, c.channels);
    std::string error;
    ASSERT_TRUE(writeImage(path, 7, 5, c.channels, data.data(), error)) << error;
    ImageData image;
    ASSERT_TRUE(readImage(path, image, error)) << error;
    std::remove(path.c_str());
    ASSERT_EQ(image.xres, 7);
    ASSERT_EQ(image.yres, 5);
    ASSERT_EQ(image.channels, c.channels);
    // EXR stores channels sorted by name: compare by name.
    for (int ch = 0; ch < c.channels; ++ch) {
      int read = channelIndex(image, c.names[ch]);
      ASSERT_GE(read, 0) << c.names[ch];
      for (int p = 0; p < 35; ++p)
        ASSERT_EQ(image.pixels[p * c.channels + read], data[p * c.channels + ch]);
    }
  }
}

TEST(ImageOutput, EightBitFormatsAreConverted) {
  std::string path = tempPath("rgb.png");
  std::vector<float> data = {0.0f, 0.5f, 1.0f, 2.0f, -1.0f, 0.25f};
  std::string error;
  ASSERT_TRUE(writeImage(path, 2, 1, 3, data.data(), error)) << error;
  ImageData image;
  ASSERT_TRUE(readImage(path, image, error)) << error;
  std::remove(path.c_str());
  ASSERT_EQ(image.pixels.size(), 6u);
  EXPECT_EQ(image.pixels[0], 0.0f);
  EXPECT_NEAR(image.pixels[1], 0.5f, 1.0f / 255);
  EXPECT_EQ(image.pixels[2], 1.0f);
  EXPECT_EQ(image.pixels[3], 1.0f); // clamped
  EXPECT_EQ(image.pixels[4], 0.0f);
}

TEST(ImageOutput, NullDiscards) {
  float pixel = 1.0f;
  std::string error;
  EXPECT_TRUE(writeImage("null", 1, 1, 1, &pixel, error));
  EXPECT_NE(access("null", F_OK), 0);
}

TEST(ImageOutput, ReportsErrors) {
  float pixel = 1.0f;
  std::string error;
  EXPECT_FALSE(writeImage(tempPath("x.nosuchformat"), 1, 1, 1, &pixel, error));
  EXPECT_FALSE(error.empty());
  error.clear();
  EXPECT_FALSE(writeImage("/nonexistent_dir/x.exr", 1, 1, 1, &pixel, error));
  EXPECT_FALSE(error.empty());
  ImageData image;
  EXPECT_FALSE(readImage("/nonexistent_dir/x.exr", image, error));
}
