//===- ThreadPool.cpp - Fixed pool of threads for grid shading -------------===//

#include "OslRuntime/ThreadPool.h"

namespace osl {

namespace {
// The pool and worker index the current thread is running a task for, so a
// nested parallelFor runs inline instead of waiting on itself.
thread_local const ThreadPool *currentPool = nullptr;
thread_local int currentWorker = 0;

/// Marks the current thread as running tasks of `pool` for a scope.
struct InPool {
  const ThreadPool *savedPool;
  int savedWorker;
  InPool(const ThreadPool *pool, int worker)
      : savedPool(currentPool), savedWorker(currentWorker) {
    currentPool = pool;
    currentWorker = worker;
  }
  ~InPool() {
    currentPool = savedPool;
    currentWorker = savedWorker;
  }
};
} // namespace

ThreadPool::ThreadPool(int threads) {
  if (threads <= 0)
    threads = static_cast<int>(std::thread::hardware_concurrency());
  numThreads = threads > 0 ? threads : 1;
  // The calling thread is participant 0, so only size()-1 threads start.
  for (int w = 1; w < numThreads; ++w)
    workers.emplace_back([this, w] { workerLoop(w); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(mutex);
    stopping = true;
  }
  wake.notify_all();
  for (std::thread &t : workers)
    t.join();
}

void ThreadPool::parallelFor(int ntasks, const std::function<void(int)> &fn) {
  parallelForWithWorker(ntasks, [&fn](int task, int) { fn(task); });
}

void ThreadPool::parallelForWithWorker(
    int ntasks, const std::function<void(int, int)> &fn) {
  if (ntasks <= 0)
    return;
  if (currentPool == this) {
    for (int t = 0; t < ntasks; ++t)
      fn(t, currentWorker);
    return;
  }
  if (numThreads == 1 || ntasks == 1) {
    InPool in(this, 0);
    for (int t = 0; t < ntasks; ++t)
      fn(t, 0);
    return;
  }

  std::lock_guard<std::mutex> call(callMutex);
  InPool in(this, 0);
  {
    std::lock_guard<std::mutex> lock(mutex);
    job = &fn;
    jobTasks = ntasks;
    nextTask = 0;
    pendingTasks = ntasks;
    ++generation;
  }
  wake.notify_all();
  runTasks(0);
  std::unique_lock<std::mutex> lock(mutex);
  done.wait(lock, [this] { return pendingTasks == 0; });
  job = nullptr;
}

void ThreadPool::runTasks(int worker) {
  std::unique_lock<std::mutex> lock(mutex);
  // Tasks are coarse (tiles of many batches), so a mutex per hand-out costs
  // nothing measurable and keeps the bookkeeping obvious.
  while (job && nextTask < jobTasks) {
    int task = nextTask++;
    const auto *fn = job;
    lock.unlock();
    (*fn)(task, worker);
    lock.lock();
    if (--pendingTasks == 0)
      done.notify_all();
  }
}

void ThreadPool::workerLoop(int worker) {
  InPool in(this, worker);
  unsigned seen = 0;
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex);
      wake.wait(lock, [&] { return stopping || generation != seen; });
      if (stopping)
        return;
      seen = generation;
    }
    runTasks(worker);
  }
}

} // namespace osl
