//===- ThreadPool.h - Fixed pool of threads for grid shading ----*- C++ -*-===//
//
// A deliberately small pool: grid shading only needs "run N independent
// tasks and wait". Threads are created once so repeated shading runs (bench
// iterations) do not pay thread start-up each time.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRUNTIME_THREADPOOL_H
#define OSLRUNTIME_THREADPOOL_H

#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace osl {

class ThreadPool {
public:
  /// `threads` participants in each parallelFor, the calling thread
  /// included; 0 means std::thread::hardware_concurrency().
  explicit ThreadPool(int threads = 0);
  ~ThreadPool();
  ThreadPool(const ThreadPool &) = delete;
  ThreadPool &operator=(const ThreadPool &) = delete;

  /// Number of participants; worker indices are in [0, size()).
  int size() const { return numThreads; }

  /// Runs fn(task) for every task in [0, ntasks) and returns when all are
  /// done. Tasks are handed out in increasing order to whichever thread is
  /// free. Calls from several threads are serialised; a call from inside a
  /// task runs inline on that thread (no deadlock).
  void parallelFor(int ntasks, const std::function<void(int task)> &fn);

  /// As parallelFor, also passing the index of the running thread so the
  /// caller can keep per-thread scratch buffers. The calling thread is 0.
  void parallelForWithWorker(int ntasks,
                             const std::function<void(int task, int worker)> &fn);

private:
  void workerLoop(int worker);
  void runTasks(int worker);

  int numThreads;
  std::vector<std::thread> workers;

  std::mutex callMutex; // one parallelFor at a time
  std::mutex mutex;     // guards the job fields below
  std::condition_variable wake, done;
  const std::function<void(int, int)> *job = nullptr;
  int jobTasks = 0;
  int nextTask = 0;     // next task index to hand out
  int pendingTasks = 0; // tasks not yet finished
  unsigned generation = 0; // bumped per job so workers see a new one
  bool stopping = false;
};

} // namespace osl

#endif // OSLRUNTIME_THREADPOOL_H
