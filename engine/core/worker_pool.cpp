// worker_pool.cpp — condition-variable pool with contiguous blocks per thread.
#include "engine/core/worker_pool.h"

#include <utility>

namespace engine {

WorkerPool::WorkerPool(int threads) {
  for (int w = 1; w < threads; ++w) workers_.emplace_back([this, w] { workerLoop(w); });
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  start_.notify_all();
  for (std::thread& t : workers_) t.join();
}

void WorkerPool::parallelFor(int n, const std::function<void(int)>& fn) {
  const int t = threads();
  if (t == 1 || n <= 1) {
    for (int i = 0; i < n; ++i) fn(i);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    job_ = &fn;
    n_ = n;
    pending_ = t - 1;
    ++generation_;
  }
  start_.notify_all();
  // the caller takes block 0
  const int end = n / t + (0 < n % t ? 1 : 0);
  try {
    for (int i = 0; i < end; ++i) fn(i);
  } catch (...) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!error_) error_ = std::current_exception();
  }
  std::unique_lock<std::mutex> lock(mutex_);
  done_.wait(lock, [this] { return pending_ == 0; });
  job_ = nullptr;
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
}

void WorkerPool::workerLoop(int worker) {
  long seen = 0;
  for (;;) {
    const std::function<void(int)>* job;
    int n;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      start_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      job = job_;
      n = n_;
    }
    const int t = threads(), base = n / t, extra = n % t;
    const int begin = worker * base + std::min(worker, extra);
    const int end = begin + base + (worker < extra ? 1 : 0);
    std::exception_ptr error;
    try {
      for (int i = begin; i < end; ++i) (*job)(i);
    } catch (...) {
      error = std::current_exception();
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (error && !error_) error_ = error;
      --pending_;
    }
    done_.notify_one();
  }
}

}  // namespace engine
