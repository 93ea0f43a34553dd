//===- Stats.cpp - Named stage timings --------------------------------------===//

#include "OslRuntime/Stats.h"

#include "llvm/Support/Format.h"
#include "llvm/Support/raw_ostream.h"

#include <algorithm>
#include <chrono>
#include <ctime>

namespace osl {

double Stats::now(Clock clock) {
  if (clock == Clock::ThreadCpu) {
    timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
  }
  return std::chrono::duration<double>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

void Stats::add(const std::string &name, double seconds) {
  for (auto &stage : stages)
    if (stage.first == name) {
      stage.second += seconds;
      return;
    }
  stages.emplace_back(name, seconds);
}

double Stats::get(const std::string &name) const {
  for (const auto &stage : stages)
    if (stage.first == name)
      return stage.second;
  return 0;
}

void Stats::print(llvm::raw_ostream &os) const {
  size_t width = 5; // "total"
  double total = 0;
  for (const auto &stage : stages) {
    width = std::max(width, stage.first.size());
    total += stage.second;
  }
  auto line = [&](llvm::StringRef name, double seconds) {
    os << "  " << name;
    os.indent(width - name.size());
    os << llvm::format(" %10.3f ms\n", seconds * 1e3);
  };
  for (const auto &stage : stages)
    line(stage.first, stage.second);
  line("total", total);
}

} // namespace osl
