//===- PixelConversion.cpp - Stored pixel types, as OpenImageIO converts --===//
#include "PixelConversion.h"
#include "OslRuntime/Grid.h"

#include <Imath/half.h>
#include <OpenImageIO/fmath.h>

#include <cstdint>
#include <cstring>
#include <vector>

namespace osl::image {

size_t pixelTypeBytes(PixelType type) {
  switch (type) {
  case PixelType::UInt8: return 1;
  case PixelType::UInt16:
  case PixelType::Half: return 2;
  case PixelType::Float:
  case PixelType::Int32: return 4;
  }
  return 4;
}

bool pixelTypeNamed(const std::string &name, PixelType &type) {
  if (name == "uint8")
    type = PixelType::UInt8;
  else if (name == "uint16")
    type = PixelType::UInt16;
  else if (name == "half")
    type = PixelType::Half;
  else if (name == "float")
    type = PixelType::Float;
  else
    return false;
  return true;
}

namespace {


template <typename D> void fromInts(const int32_t *ints, size_t count, void *out) {
  OIIO::convert_type<int32_t, D>(ints, static_cast<D *>(out), count);
}

} // namespace

const float *floatValues(const float *data, size_t count, bool intBits,
                         std::vector<float> &scratch) {
  if (!intBits)
    return data;
  scratch.resize(count);
  for (size_t i = 0; i < count; ++i)
    scratch[i] = float(intOutputValue(data[i]));
  return scratch.data();
}

void convertPixels(const float *values, size_t count, bool integerPixels, PixelType type,
                   void *out) {
  if (integerPixels) {
    std::vector<int32_t> ints(count);
    for (size_t i = 0; i < count; ++i)
      ints[i] = intOutputValue(values[i]);
    switch (type) {
    case PixelType::UInt8: return fromInts<uint8_t>(ints.data(), count, out);
    case PixelType::UInt16: return fromInts<uint16_t>(ints.data(), count, out);
    case PixelType::Half: return fromInts<Imath::half>(ints.data(), count, out);
    case PixelType::Float: return fromInts<float>(ints.data(), count, out);
    case PixelType::Int32: std::memcpy(out, ints.data(), count * sizeof(int32_t)); return;
    }
    return;
  }
  switch (type) {
  case PixelType::UInt8:
    return OIIO::convert_type<float, uint8_t>(values, static_cast<uint8_t *>(out), count);
  case PixelType::UInt16:
    return OIIO::convert_type<float, uint16_t>(values, static_cast<uint16_t *>(out), count);
  case PixelType::Half: {
    auto *halves = static_cast<Imath::half *>(out);
    for (size_t i = 0; i < count; ++i)
      halves[i] = Imath::half(values[i]);
    return;
  }
  case PixelType::Float: std::memcpy(out, values, count * sizeof(float)); return;
  case PixelType::Int32: {
    auto *ints = static_cast<int32_t *>(out);
    for (size_t i = 0; i < count; ++i)
      ints[i] = osl::wholeNumber(values[i]);
    return;
  }
  }
}

void convertToFloat(const void *stored, PixelType type, size_t count, float *out) {
  switch (type) {
  case PixelType::UInt8:
    return OIIO::convert_type<uint8_t, float>(static_cast<const uint8_t *>(stored), out, count);
  case PixelType::UInt16:
    return OIIO::convert_type<uint16_t, float>(static_cast<const uint16_t *>(stored), out,
                                               count);
  case PixelType::Half: {
    const auto *halves = static_cast<const Imath::half *>(stored);
    for (size_t i = 0; i < count; ++i)
      out[i] = float(halves[i]);
    return;
  }
  case PixelType::Float: std::memcpy(out, stored, count * sizeof(float)); return;
  case PixelType::Int32:
    return OIIO::convert_type<int32_t, float>(static_cast<const int32_t *>(stored), out,
                                              count);
  }
}

} // namespace osl::image
