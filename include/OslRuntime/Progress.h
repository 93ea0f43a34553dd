//===- Progress.h - A progress bar on stderr --------------------*- C++ -*-===//
#ifndef OSLRUNTIME_PROGRESS_H
#define OSLRUNTIME_PROGRESS_H

#include <atomic>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <unistd.h>

namespace osl {

/// Progress bar on stderr for long interactive runs; silent otherwise so
/// logs and piped output stay clean.
class Progress {
public:
  /// `label` names the work ("shading", "rendering"); `total` its units.
  Progress(bool wanted, long total, const char *label)
      : enabled(wanted && isatty(STDERR_FILENO) && total > 0), total(total), label(label),
        start(std::chrono::steady_clock::now()) {}

  void add(long units) {
    if (!enabled)
      return;
    long now = done.fetch_add(units) + units;
    double t = elapsed();
    if (t < 1.0 || t - lastPrint.load() < 0.1)
      return;
    std::unique_lock<std::mutex> lock(printMutex, std::try_to_lock);
    if (!lock.owns_lock())
      return;
    lastPrint = t;
    draw(now);
    shown = true;
  }

  void finish() {
    if (!shown)
      return;
    draw(total);
    std::fputc('\n', stderr);
  }

private:
  double elapsed() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                         start)
        .count();
  }
  void draw(long n) {
    constexpr int kBar = 40;
    int fill = static_cast<int>(kBar * n / total);
    char bar[kBar + 1];
    for (int i = 0; i < kBar; ++i)
      bar[i] = i < fill ? '=' : ' ';
    bar[kBar] = 0;
    std::fprintf(stderr, "\r%s [%s] %3d%%", label, bar,
                 static_cast<int>(100 * n / total));
    std::fflush(stderr);
  }

  bool enabled;
  long total;
  const char *label;
  std::chrono::steady_clock::time_point start;
  std::atomic<long> done{0};
  std::atomic<double> lastPrint{0};
  std::mutex printMutex;
  bool shown = false;
};

} // namespace osl

#endif // OSLRUNTIME_PROGRESS_H
