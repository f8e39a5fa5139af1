#pragma once
// The swarm's client side: submits the studies and watches each one's progress stream to
// its end (reconnecting across a coordinator restart), counting the stream's traffic.
#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "gaitforge/v1/study.pb.h"

namespace gaitforge::swarm {

struct WatchTraffic {
  std::atomic<int64_t> messages{0}, bytes{0}, reconnects{0};
};

// Creates `count` studies from `spec`, the i-th with seed spec.seed + i. Returns their ids.
absl::StatusOr<std::vector<std::string>> SubmitStudies(const std::string& target,
                                                       const std::string& token,
                                                       const v1::StudySpec& spec, int count);

// Watches every study until none is running; returns each study's final state
// ("completed", "failed", ...), in order.
std::vector<std::string> WatchToEnd(const std::string& target, const std::string& token,
                                    const std::vector<std::string>& ids, WatchTraffic& traffic);

}  // namespace gaitforge::swarm
