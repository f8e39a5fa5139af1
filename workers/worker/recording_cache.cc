#include "workers/worker/recording_cache.h"

#include "absl/strings/str_cat.h"

namespace gaitforge::worker {

absl::StatusOr<std::shared_ptr<const recording::Recording>> RecordingCache::Get(
    const std::string& hash, const robots::RobotDescriptor* robot) {
  {
    std::lock_guard<std::mutex> l(mu_);
    auto it = entries_.find(hash);
    if (it != entries_.end()) {
      lru_.remove(hash);
      lru_.push_front(hash);
      return it->second.recording;
    }
  }
  auto bytes = fetch_(hash);
  if (!bytes.ok()) return bytes.status();
  if (recording::ContentHash(bytes->csv, bytes->sidecar) != hash)
    return absl::DataLossError(absl::StrCat("recording ", hash, ": fetched bytes do not match it"));
  // The coordinator enforced its size limit on upload; the worker takes what it serves.
  recording::RecordingLimits limits;
  limits.max_bytes = static_cast<size_t>(1) << 40;
  auto parsed = recording::ParseRecording(bytes->csv, bytes->sidecar, bytes->name,
                                          bytes->name + ".json", limits, robot);
  if (!parsed.ok()) return parsed.status();
  auto rec = std::make_shared<const recording::Recording>(std::move(*parsed));
  const size_t size = bytes->csv.size() + bytes->sidecar.size();
  std::lock_guard<std::mutex> l(mu_);
  ++fetches_;
  if (!entries_.count(hash)) {
    entries_[hash] = Entry{rec, size};
    lru_.push_front(hash);
    bytes_ += size;
    while (bytes_ > max_bytes_ && lru_.size() > 1) {
      const std::string old = lru_.back();
      lru_.pop_back();
      bytes_ -= entries_[old].bytes;
      entries_.erase(old);
    }
  }
  return rec;
}

size_t RecordingCache::size() const {
  std::lock_guard<std::mutex> l(mu_);
  return entries_.size();
}

}  // namespace gaitforge::worker
