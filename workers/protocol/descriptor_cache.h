#pragma once
// Robot descriptors by content hash. A leased job names its study's descriptor by hash
// (objective.robot_descriptor_hash) instead of carrying the text; the worker fetches each
// text once (WorkerService.GetRobot), checks that it hashes to the name, keeps it, and puts
// it back into the jobs before evaluating them. Shared by gaitforge-worker and bench/swarm.
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>

#include "absl/status/statusor.h"
#include "gaitforge/v1/worker.pb.h"

namespace gaitforge::worker {

class DescriptorCache {
 public:
  // fetch(hash): the text from the coordinator, or the call's error.
  using Fetch = std::function<absl::StatusOr<std::string>(const std::string& hash)>;
  explicit DescriptorCache(Fetch fetch) : fetch_(std::move(fetch)) {}

  // The text whose content hash is `hash`: cached, or fetched and checked (DATA_LOSS when
  // the bytes do not hash to `hash`, which is never cached).
  absl::StatusOr<std::string> Get(const std::string& hash);
  // Puts the text back into every job of `lease` that names one by hash. Stops at the
  // first error and returns it (the caller retries transient ones).
  absl::Status Fill(v1::LeaseResponse& lease);
  int64_t fetches() const;

 private:
  Fetch fetch_;
  mutable std::mutex mu_;
  std::map<std::string, std::string> texts_;
  int64_t fetches_ = 0;
};

}  // namespace gaitforge::worker
