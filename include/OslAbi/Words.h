//===- Words.h - 32-bit row words as floats and back --------------*- C++ -*-===//
//
// The runtime's rows (Strings.h) hold every value as a 32-bit word: an int
// or handle as it is, a float as its bits.
//
//===----------------------------------------------------------------------===//
#ifndef OSLABI_WORDS_H
#define OSLABI_WORDS_H

#include <cstdint>
#include <cstring>

namespace osl {

inline float floatOfWord(int32_t word) {
  float f;
  std::memcpy(&f, &word, sizeof f);
  return f;
}

inline int32_t wordOfFloat(float f) {
  int32_t word;
  std::memcpy(&word, &f, sizeof word);
  return word;
}

} // namespace osl

#endif // OSLABI_WORDS_H
