#include "workers/worker/batch_runner.h"

namespace gaitforge::worker {

BatchRunner::BatchRunner(int threads, std::function<void()> thread_init)
    : thread_init_(std::move(thread_init)) {
  for (int i = 0; i < threads; ++i) threads_.emplace_back([this] { Loop(); });
}

BatchRunner::~BatchRunner() {
  {
    std::lock_guard<std::mutex> l(mu_);
    stop_ = true;
  }
  start_cv_.notify_all();
  for (auto& t : threads_) t.join();
}

void BatchRunner::Run(int n, const std::function<void(int)>& fn) {
  std::unique_lock<std::mutex> l(mu_);
  fn_ = &fn;
  n_ = n;
  next_ = 0;
  done_ = 0;
  ++batch_;
  start_cv_.notify_all();
  done_cv_.wait(l, [&] { return done_ == n_; });
  fn_ = nullptr;
}

void BatchRunner::Loop() {
  if (thread_init_) thread_init_();
  std::unique_lock<std::mutex> l(mu_);
  for (;;) {
    start_cv_.wait(l, [&] { return stop_ || (fn_ && next_ < n_); });
    if (stop_) return;
    const int i = next_++;
    const auto* fn = fn_;
    l.unlock();
    (*fn)(i);
    l.lock();
    if (++done_ == n_) done_cv_.notify_all();
  }
}

}  // namespace gaitforge::worker
