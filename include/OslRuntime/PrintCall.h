//===- PrintCall.h - printf, fprintf, warning, error: the ABI ----*- C++ -*-===//
//
// A kernel calls osl_rt_print once per osl.print and batch, with the
// operands as rows of W 32-bit values (StringCall.h's layout). Each active
// lane's text is kept per lane until the batch ends; the grid then takes
// the batch's text (takeBatchPrints) so that output comes out in point
// order at every width and thread count, as testshade's scalar order is.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRUNTIME_PRINTCALL_H
#define OSLRUNTIME_PRINTCALL_H

#include <cstdint>
#include <iterator>
#include <string>
#include <string_view>
#include <vector>

namespace osl {

/// Where an osl.print's text goes, with the operand kinds before the
/// values: `s` the format string, and fprintf's file name before it.
/// "renderer_error" is the renderer's own report of a bad request (an
/// unknown space name), printed as testshade's renderer prints it.
struct PrintStream {
  const char *name;
  const char *operands;
};
inline constexpr PrintStream kPrintStreams[] = {
    {"printf", "s"}, {"fprintf", "ss"}, {"warning", "s"}, {"error", "s"}, {"renderer_error", "s"}};

/// The index of a print stream in kPrintStreams, or -1.
constexpr int32_t printStreamCode(std::string_view name) {
  for (int32_t i = 0; i < int32_t(std::size(kPrintStreams)); ++i)
    if (name == kPrintStreams[i].name)
      return i;
  return -1;
}

/// One text a lane printed: `stream` indexes kPrintStreams; `file` is
/// fprintf's.
struct PrintedText {
  int32_t stream;
  std::string file, text;
};

/// What shading printed, in point order (each point's calls in program
/// order): what testshade's journal holds.
struct PrintLog {
  std::vector<PrintedText> texts;
  bool empty() const { return texts.empty(); }
};

/// Moves what this thread's kernels printed since the last call to the end
/// of `log`, lane by lane.
void takeBatchPrints(PrintLog &log);

/// Emits `log` in order as testshade does: printf's text to standard
/// output, fprintf's to its files, and each warning or error to standard
/// error as "ERROR: Shader error [NAME]: text" - a text already reported
/// in this process is not repeated, unless `repeatReports` (testshade's
/// `--options error_repeats=1`). Returns the number of errors reported.
int emitPrints(const PrintLog &log, const std::string &shaderName,
               bool repeatReports = false);

/// Keeps one lane's text for the batch (osl_rt_print's work once a lane
/// is formatted); `file` is fprintf's file name.
void keepLaneText(int32_t stream, int32_t lane, std::string file, std::string text);

} // namespace osl

/// Formats the active lanes' operands (stream `stream` of kPrintStreams;
/// `kinds` as osl.print's) and keeps each lane's text for the batch. A
/// format error is reported once at `where`.
extern "C" void osl_rt_print(const char *where, int32_t stream, const char *kinds,
                             int32_t *rows, int32_t width, uint32_t laneMask);

#endif // OSLRUNTIME_PRINTCALL_H
