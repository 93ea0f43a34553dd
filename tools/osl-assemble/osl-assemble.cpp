//===- osl-assemble.cpp - Tiles into one image ----------------------------===//
//
//   osl-assemble W H OUT [-od TYPE] [--int] TILE X Y [TILE X Y ...]
//
// Reads float tiles (osl-run --crop writes them as EXR), places each with
// its top-left pixel at (X, Y) of a W x H image and writes OUT as osl-run
// writes an image: -od's stored type, --int for an int output. Every pixel
// must come from exactly one tile. The tiles' floats are the image's, so
// OUT is the file one osl-run over the whole grid writes (for an int
// output, one whose ints a float holds exactly: up to 2^24).
//
//===----------------------------------------------------------------------===//
#include "OslRuntime/Grid.h"
#include "OslRuntime/ImageOutput.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

int fail(const std::string &message) {
  std::fprintf(stderr, "osl-assemble: error: %s\n", message.c_str());
  return 1;
}

bool parseInt(const char *text, int &value) {
  char *end = nullptr;
  long v = std::strtol(text, &end, 10);
  if (!*text || *end || v < 0 || v > (1L << 30))
    return false;
  value = int(v);
  return true;
}

} // namespace

int main(int argc, char **argv) {
  int width = 0, height = 0;
  if (argc < 4 || !parseInt(argv[1], width) || !parseInt(argv[2], height) || width == 0 ||
      height == 0)
    return fail("usage: osl-assemble W H OUT [-od TYPE] [--int] TILE X Y [TILE X Y ...]");
  std::string out = argv[3], dataType;
  bool integer = false;
  int i = 4;
  for (; i < argc && argv[i][0] == '-'; ++i) {
    if (std::strcmp(argv[i], "-od") == 0 && i + 1 < argc)
      dataType = argv[++i];
    else if (std::strcmp(argv[i], "--int") == 0)
      integer = true;
    else
      return fail(std::string("unknown option '") + argv[i] + "'");
  }
  if (i == argc || (argc - i) % 3 != 0)
    return fail("tiles come as TILE X Y");
  int channels = 0;
  std::vector<float> image;
  std::vector<unsigned char> covered(size_t(width) * height, 0);
  for (; i < argc; i += 3) {
    int x0 = 0, y0 = 0;
    if (!parseInt(argv[i + 1], x0) || !parseInt(argv[i + 2], y0))
      return fail(std::string("bad position for tile ") + argv[i]);
    osl::ImageData tile;
    std::string error;
    if (!osl::readImage(argv[i], tile, error))
      return fail(error);
    if (channels == 0) {
      channels = tile.channels;
      image.assign(size_t(width) * height * channels, 0.0f);
    }
    if (tile.channels != channels)
      return fail(std::string(argv[i]) + " has " + std::to_string(tile.channels) +
                  " channels, the first tile " + std::to_string(channels));
    if (x0 + tile.xres > width || y0 + tile.yres > height)
      return fail(std::string(argv[i]) + " at (" + argv[i + 1] + ", " + argv[i + 2] +
                  ") reaches past the " + std::to_string(width) + "x" +
                  std::to_string(height) + " image");
    for (int y = 0; y < tile.yres; ++y)
      for (int x = 0; x < tile.xres; ++x) {
        size_t pixel = size_t(y0 + y) * width + size_t(x0 + x);
        if (covered[pixel]++)
          return fail(std::string(argv[i]) + " overlaps another tile at (" +
                      std::to_string(x0 + x) + ", " + std::to_string(y0 + y) + ")");
        std::memcpy(&image[pixel * channels], &tile.pixels[(size_t(y) * tile.xres + x) * channels],
                    sizeof(float) * channels);
      }
  }
  for (size_t p = 0; p < covered.size(); ++p)
    if (!covered[p])
      return fail("no tile covers pixel (" + std::to_string(p % width) + ", " +
                  std::to_string(p / width) + ")");
  // writeImage takes an int output as its ints' bits (OslRuntime/Grid.h);
  // the tiles hold the values as floats.
  if (integer)
    for (float &value : image)
      value = osl::intOutputBits(osl::wholeNumber(value));
  std::string error;
  if (!osl::writeImage(out, width, height, channels, image.data(), error, dataType, integer,
                       /*asTestshade=*/true))
    return fail(error);
  return 0;
}
