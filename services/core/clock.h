#pragma once
// Injected time, so that lease expiry and timing can be tested without sleeping.
#include <atomic>
#include <cstdint>

namespace gaitforge::core {

class Clock {
 public:
  virtual ~Clock() = default;
  // Monotonic milliseconds (only differences are meaningful).
  virtual int64_t NowMs() const = 0;
  // Wall-clock Unix milliseconds, for records shown to users.
  virtual int64_t UnixMs() const = 0;
};

// The process's real clocks (steady_clock and system_clock).
Clock& RealClock();

// A clock that only moves when told to; for tests.
class ManualClock final : public Clock {
 public:
  int64_t NowMs() const override { return now_.load(); }
  int64_t UnixMs() const override { return 1'700'000'000'000 + now_.load(); }
  void Advance(int64_t ms) { now_ += ms; }

 private:
  std::atomic<int64_t> now_{0};
};

}  // namespace gaitforge::core
