#include "bench/swarm/event_loop.h"

namespace gaitforge::swarm {

void EventLoop::At(Clock::time_point when, Task task) {
  {
    std::lock_guard<std::mutex> l(mu_);
    queue_.push(Entry{when, seq_++, std::move(task)});
  }
  cv_.notify_one();
}

void EventLoop::Stop() {
  {
    std::lock_guard<std::mutex> l(mu_);
    stop_ = true;
  }
  cv_.notify_one();
}

void EventLoop::Run() {
  std::unique_lock<std::mutex> l(mu_);
  while (!stop_) {
    if (queue_.empty()) {
      cv_.wait(l);
      continue;
    }
    const auto when = queue_.top().when;
    if (when > Clock::now()) {
      cv_.wait_until(l, when);
      continue;
    }
    Task task = std::move(const_cast<Entry&>(queue_.top()).task);
    queue_.pop();
    l.unlock();
    task();
    l.lock();
  }
}

}  // namespace gaitforge::swarm
