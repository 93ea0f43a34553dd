//===- Stats.h - Named stage timings for --stats ----------------*- C++ -*-===//
//
// The driver reports where time goes (parse, MLIR passes, LLVM O3, JIT
// codegen, shading, image write) so regressions in JIT latency show up next
// to shading time. Kept free of LLVM headers except a forward declaration.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRUNTIME_STATS_H
#define OSLRUNTIME_STATS_H

#include <string>
#include <utility>
#include <vector>

namespace llvm {
class raw_ostream;
} // namespace llvm

namespace osl {

/// Seconds spent per named stage, in the order stages were first added.
/// Adding a stage name twice accumulates, so repeated steps (one lookup per
/// kernel) show as one line. Not thread-safe: record from one thread.
struct Stats {
  /// What a stage's time is: wall time (osl-run --stats), or the CPU time
  /// of the recording thread, which other processes on a busy machine do
  /// not inflate (the JIT benchmark).
  enum class Clock { Wall, ThreadCpu };
  Clock clock = Clock::Wall;
  std::vector<std::pair<std::string, double>> stages;

  /// Now on `clock`, in seconds from an arbitrary origin.
  static double now(Clock clock);

  void add(const std::string &name, double seconds);
  /// Seconds recorded for `name`, or 0.
  double get(const std::string &name) const;
  /// One aligned line per stage in milliseconds, then the total.
  void print(llvm::raw_ostream &os) const;
};

/// Adds the lifetime of this object to `stats` under `name`; a null `stats`
/// makes it a no-op so callers need not branch.
class ScopedTimer {
public:
  ScopedTimer(Stats *stats, std::string name)
      : stats(stats), name(std::move(name)),
        start(stats ? Stats::now(stats->clock) : 0) {}
  ~ScopedTimer() { stop(); }
  ScopedTimer(const ScopedTimer &) = delete;
  ScopedTimer &operator=(const ScopedTimer &) = delete;

  /// Records now instead of at destruction; later calls do nothing.
  void stop() {
    if (!stats)
      return;
    stats->add(name, Stats::now(stats->clock) - start);
    stats = nullptr;
  }

private:
  Stats *stats;
  std::string name;
  double start;
};

} // namespace osl

#endif // OSLRUNTIME_STATS_H
