//===- Print.cpp - printf, fprintf, warning and error in point order ------===//
//
// A batch's lanes print in lane order, one lane's calls in program order:
// each thread keeps the texts of the batch it runs, tagged with their lane,
// and the grid takes them when the batch ends (takeBatchPrints) and emits
// batches in order. Warnings and errors are collected for the run and
// reported once per distinct text, as testshade's error handler does.
//
//===----------------------------------------------------------------------===//
#include "OslRuntime/PrintCall.h"

#include <algorithm>
#include <cstdio>
#include <mutex>
#include <set>

namespace {

struct LaneText {
  int32_t lane, stream;
  std::string file, text;
};

std::vector<LaneText> &threadTexts() {
  thread_local std::vector<LaneText> texts;
  return texts;
}

enum : int32_t { kPrintf, kFprintf, kWarning, kError };

std::mutex messageMutex;
std::vector<std::pair<int32_t, std::string>> runMessages;

} // namespace

void osl::keepLaneText(int32_t stream, int32_t lane, std::string file, std::string text) {
  threadTexts().push_back({lane, stream, std::move(file), std::move(text)});
}

void osl::takeBatchPrints(BatchPrints &prints) {
  std::vector<LaneText> &texts = threadTexts();
  std::stable_sort(texts.begin(), texts.end(),
                   [](const LaneText &a, const LaneText &b) { return a.lane < b.lane; });
  for (LaneText &t : texts) {
    if (t.stream == kPrintf)
      prints.out += t.text;
    else if (t.stream == kFprintf)
      prints.files.emplace_back(std::move(t.file), std::move(t.text));
    else
      prints.messages.emplace_back(t.stream, std::move(t.text));
  }
  texts.clear();
}

void osl::emitBatchPrints(const BatchPrints &prints) {
  std::fwrite(prints.out.data(), 1, prints.out.size(), stdout);
  for (const auto &[file, text] : prints.files) {
    if (FILE *f = std::fopen(file.c_str(), "a")) {
      std::fwrite(text.data(), 1, text.size(), f);
      std::fclose(f);
    } else {
      std::lock_guard<std::mutex> lock(messageMutex);
      runMessages.emplace_back(kError, "fprintf: cannot open \"" + file + "\" for writing");
    }
  }
  std::lock_guard<std::mutex> lock(messageMutex);
  runMessages.insert(runMessages.end(), prints.messages.begin(), prints.messages.end());
}

int osl::printMessages(const std::string &shaderName) {
  std::lock_guard<std::mutex> lock(messageMutex);
  std::set<std::pair<int32_t, std::string>> seen;
  int errors = 0;
  std::fflush(stdout);
  for (const auto &m : runMessages) {
    if (!seen.insert(m).second)
      continue;
    bool error = m.first == kError;
    errors += error;
    std::fprintf(stderr, "%s: Shader %s [%s]: %s\n", error ? "ERROR" : "WARNING",
                 error ? "error" : "warning", shaderName.c_str(), m.second.c_str());
  }
  runMessages.clear();
  return errors;
}
