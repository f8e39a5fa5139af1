#pragma once
// One thread that runs every emulated worker's steps: tasks posted from gRPC's callback
// threads, and timers (an evaluation's end, the next heartbeat, a backoff). Keeping all
// worker state on this thread makes the emulated workers lock-free and cheap.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <queue>
#include <vector>

namespace gaitforge::swarm {

using Clock = std::chrono::steady_clock;

class EventLoop {
 public:
  using Task = std::function<void()>;
  // Runs `task` on the loop thread as soon as possible (any thread may call this).
  void Post(Task task) { At(Clock::now(), std::move(task)); }
  // Runs `task` on the loop thread at `when` (any thread may call this).
  void At(Clock::time_point when, Task task);
  void After(int ms, Task task) { At(Clock::now() + std::chrono::milliseconds(ms), std::move(task)); }
  // Runs tasks until Stop(); returns then, dropping the tasks not yet due.
  void Run();
  void Stop();

 private:
  struct Entry {
    Clock::time_point when;
    uint64_t seq;
    Task task;
    bool operator>(const Entry& o) const {
      return when != o.when ? when > o.when : seq > o.seq;
    }
  };
  std::mutex mu_;
  std::condition_variable cv_;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue_;
  uint64_t seq_ = 0;
  bool stop_ = false;
};

}  // namespace gaitforge::swarm
