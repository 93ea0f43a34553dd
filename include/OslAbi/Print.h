//===- Print.h - printf, fprintf, warning, error: the streams ----*- C++ -*-===//
//
// A kernel calls osl_rt_print (EntryPoints.h) once per osl.print and batch,
// with the operands as rows of W 32-bit values (Strings.h's layout) and the
// stream's index in the table below.
//
//===----------------------------------------------------------------------===//
#ifndef OSLABI_PRINT_H
#define OSLABI_PRINT_H

#include <cstdint>
#include <iterator>
#include <string_view>

namespace osl {

/// Where an osl.print's text goes, with the operand kinds before the
/// values: `s` the format string, and before it fprintf's file name or,
/// for warning and error (`namesShader`), the name of the shader that
/// reports, which the compiler supplies: OSL's "Shader error [name]" names
/// the layer's shader, not the group's last. "renderer_error" is the
/// renderer's own report of a bad request (an unknown space name), printed
/// as testshade's renderer prints it.
struct PrintStream {
  const char *name;
  const char *operands;
  bool namesShader;
};
inline constexpr PrintStream kPrintStreams[] = {{"printf", "s", false},
                                                {"fprintf", "ss", false},
                                                {"warning", "ss", true},
                                                {"error", "ss", true},
                                                {"renderer_error", "s", false}};

/// The index of a print stream in kPrintStreams, or -1.
constexpr int32_t printStreamCode(std::string_view name) {
  for (int32_t i = 0; i < int32_t(std::size(kPrintStreams)); ++i)
    if (name == kPrintStreams[i].name)
      return i;
  return -1;
}

} // namespace osl

#endif // OSLABI_PRINT_H
