// worker_pool.h — a fixed set of threads that run one parallel-for at a time (the caller's thread works
// too). Used to step independent physics worlds on all cores. Results never depend on the thread count:
// each index is one environment with its own world and RNG.
#pragma once

#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace engine {

class WorkerPool {
 public:
  /// threads = total threads including the caller (>= 1).
  explicit WorkerPool(int threads);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  /// Calls fn(i) for i in [0, n), split into contiguous blocks across the threads; returns when all are done. An
  /// exception thrown by fn ends that thread's block; once every thread is done, the first one caught is rethrown
  /// here, in the caller's thread.
  void parallelFor(int n, const std::function<void(int)>& fn);

  int threads() const { return int(workers_.size()) + 1; }

 private:
  void workerLoop(int worker);

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable start_, done_;
  const std::function<void(int)>* job_ = nullptr;
  int n_ = 0;
  long generation_ = 0;
  int pending_ = 0;
  bool stop_ = false;
  std::exception_ptr error_;  ///< the first exception of the current parallelFor
};

}  // namespace engine
