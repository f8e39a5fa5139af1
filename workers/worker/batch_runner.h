#pragma once
// Runs fn(0..n-1) on a fixed set of threads and waits for all of them. Threads persist
// across batches, and each calls `thread_init` once when it starts (per-thread simulator
// setup).
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace gaitforge::worker {

class BatchRunner {
 public:
  BatchRunner(int threads, std::function<void()> thread_init = {});
  ~BatchRunner();
  BatchRunner(const BatchRunner&) = delete;
  BatchRunner& operator=(const BatchRunner&) = delete;

  void Run(int n, const std::function<void(int)>& fn);

 private:
  void Loop();

  std::mutex mu_;
  std::condition_variable start_cv_, done_cv_;
  const std::function<void(int)>* fn_ = nullptr;  // guarded by mu_
  int n_ = 0, next_ = 0, done_ = 0;                // guarded by mu_
  long batch_ = 0;                                 // guarded by mu_
  bool stop_ = false;                              // guarded by mu_
  std::function<void()> thread_init_;
  std::vector<std::thread> threads_;
};

}  // namespace gaitforge::worker
