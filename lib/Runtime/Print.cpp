//===- Print.cpp - printf, fprintf, warning and error in point order ------===//
//
// A batch's lanes print in lane order, one lane's calls in program order:
// each thread keeps the texts of the batch it runs, tagged with their lane,
// and the grid takes them when the batch ends (takeBatchPrints) into a log
// in batch order. Emitting the log reports each distinct warning or error
// once, as testshade's error handler does.
//
//===----------------------------------------------------------------------===//
#include "OslRuntime/PrintCall.h"

#include <algorithm>
#include <cstdio>
#include <mutex>
#include <set>

namespace {

struct LaneText {
  int32_t lane;
  osl::PrintedText printed;
};

std::vector<LaneText> &threadTexts() {
  thread_local std::vector<LaneText> texts;
  return texts;
}

enum : int32_t { kPrintf, kFprintf, kWarning, kError, kRendererError };

std::mutex reportedMutex;
std::set<std::pair<int32_t, std::string>> reported;

} // namespace

void osl::keepLaneText(int32_t stream, int32_t lane, std::string file, std::string text) {
  threadTexts().push_back({lane, {stream, std::move(file), std::move(text)}});
}

bool osl::batchPrinted() { return !threadTexts().empty(); }

void osl::takeBatchPrints(PrintLog &log) {
  std::vector<LaneText> &texts = threadTexts();
  if (texts.empty())
    return;
  std::stable_sort(texts.begin(), texts.end(),
                   [](const LaneText &a, const LaneText &b) { return a.lane < b.lane; });
  for (LaneText &t : texts)
    log.texts.push_back(std::move(t.printed));
  texts.clear();
}

/// The key emitPrints reports a text once by: errors and warnings apart.
static std::pair<int32_t, std::string> reportKey(const osl::PrintedText &t) {
  return {t.stream != kWarning, t.text};
}

void osl::appendPrints(PrintLog &log, PrintLog &&more, bool repeatReports) {
  for (PrintedText &t : more.texts) {
    bool report = t.stream == kWarning || t.stream == kError || t.stream == kRendererError;
    if (report && !repeatReports && !log.reports.insert(reportKey(t)).second)
      continue;
    log.texts.push_back(std::move(t));
  }
  more.texts.clear();
}

int osl::emitPrints(const PrintLog &log, const std::string &shaderName,
                    bool repeatReports) {
  int errors = 0;
  for (const PrintedText &t : log.texts) {
    if (t.stream == kPrintf) {
      std::fwrite(t.text.data(), 1, t.text.size(), stdout);
      continue;
    }
    if (t.stream == kFprintf) {
      if (FILE *f = std::fopen(t.file.c_str(), "a")) {
        std::fwrite(t.text.data(), 1, t.text.size(), f);
        std::fclose(f);
        continue;
      }
    }
    bool error = t.stream != kWarning;
    std::string text = t.stream == kFprintf
                           ? "fprintf cannot open \"" + t.file + "\" for writing"
                           : t.text;
    if (!repeatReports) {
      std::lock_guard<std::mutex> lock(reportedMutex);
      if (!reported.insert({int32_t(error), text}).second)
        continue;
    }
    errors += error;
    // Standard output first, so that a file holding both keeps the order.
    std::fflush(stdout);
    if (t.stream == kRendererError) {
      std::fprintf(stderr, "ERROR: %s\n", text.c_str());
      continue;
    }
    // warning() and error() name their shader (kPrintStreams).
    const std::string &reporter = t.file.empty() ? shaderName : t.file;
    std::fprintf(stderr, "%s: Shader %s [%s]: %s\n", error ? "ERROR" : "WARNING",
                 error ? "error" : "warning", reporter.c_str(), text.c_str());
  }
  std::fflush(stdout);
  return errors;
}
