#pragma once
// Recordings a worker's jobs name, fetched from the coordinator once and kept by content
// hash (a worker stays stateless: the cache only holds what the hash fully determines).
#include <functional>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "absl/status/statusor.h"
#include "services/recording/recording.h"

namespace gaitforge::worker {

class RecordingCache {
 public:
  struct Bytes {
    std::string name, csv, sidecar;
  };
  // fetch(hash) returns the stored bytes; UNAVAILABLE-like errors are retried by callers.
  using Fetch = std::function<absl::StatusOr<Bytes>(const std::string& hash)>;
  RecordingCache(Fetch fetch, size_t max_bytes = 512u << 20)
      : fetch_(std::move(fetch)), max_bytes_(max_bytes) {}

  // The parsed recording. Fetches on a miss; checks that the bytes hash to `hash`
  // (DATA_LOSS otherwise) and parse (INVALID_ARGUMENT otherwise); `robot` is the job's
  // robot when the study carries its descriptor (a recording may name it).
  absl::StatusOr<std::shared_ptr<const recording::Recording>> Get(
      const std::string& hash, const robots::RobotDescriptor* robot = nullptr);
  size_t size() const;
  int64_t fetches() const { return fetches_; }

 private:
  struct Entry {
    std::shared_ptr<const recording::Recording> recording;
    size_t bytes;
  };
  Fetch fetch_;
  const size_t max_bytes_;
  mutable std::mutex mu_;
  std::map<std::string, Entry> entries_;  // guarded by mu_
  std::list<std::string> lru_;            // guarded by mu_; front = most recent
  size_t bytes_ = 0;                      // guarded by mu_
  int64_t fetches_ = 0;                   // guarded by mu_
};

}  // namespace gaitforge::worker
