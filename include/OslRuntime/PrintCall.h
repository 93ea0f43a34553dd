//===- PrintCall.h - printf, fprintf, warning, error: host side --*- C++ -*-===//
//
// A kernel calls osl_rt_print (OslAbi/EntryPoints.h) once per osl.print and
// batch. Each active lane's text is kept per lane until the batch ends; the
// grid then takes the batch's text (takeBatchPrints) so that output comes
// out in point order at every width and thread count, as testshade's scalar
// order is.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRUNTIME_PRINTCALL_H
#define OSLRUNTIME_PRINTCALL_H

#include "OslAbi/Print.h"

#include <cstdint>
#include <set>
#include <string>
#include <vector>

namespace osl {

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
  /// The warnings and errors `texts` holds (appendPrints' record).
  std::set<std::pair<int32_t, std::string>> reports;
  bool empty() const { return texts.empty(); }
};

/// Moves `more` to the end of `log`; unless `repeatReports`, a warning or
/// error `log` already holds is left out, as emitPrints would leave it out:
/// many passes of a shader that reports at every point keep one copy, not
/// one per point and pass.
void appendPrints(PrintLog &log, PrintLog &&more, bool repeatReports);

/// Moves what this thread's kernels printed since the last call to the end
/// of `log`, lane by lane.
void takeBatchPrints(PrintLog &log);
/// Whether this thread's kernels printed since the last takeBatchPrints
/// (most batches print nothing: a grid asks before it makes a log).
bool batchPrinted();

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

#endif // OSLRUNTIME_PRINTCALL_H
