#include "workers/protocol/descriptor_cache.h"

#include "absl/strings/str_cat.h"
#include "services/recording/recording.h"

namespace gaitforge::worker {

absl::StatusOr<std::string> DescriptorCache::Get(const std::string& hash) {
  {
    std::lock_guard<std::mutex> l(mu_);
    if (auto it = texts_.find(hash); it != texts_.end()) return it->second;
    ++fetches_;
  }
  auto text = fetch_(hash);
  if (!text.ok()) return text.status();
  if (recording::ContentHash(*text, "") != hash)
    return absl::DataLossError(
        absl::StrCat("robot descriptor '", hash, "': the fetched text has another hash"));
  std::lock_guard<std::mutex> l(mu_);
  texts_.emplace(hash, *text);
  return *text;
}

absl::Status DescriptorCache::Fill(v1::LeaseResponse& lease) {
  for (v1::Job& job : *lease.mutable_jobs()) {
    v1::ObjectiveSpec& o = *job.mutable_objective();
    if (o.robot_descriptor_hash().empty() || !o.robot_descriptor().empty()) continue;
    auto text = Get(o.robot_descriptor_hash());
    if (!text.ok()) return text.status();
    o.set_robot_descriptor(*text);
  }
  return absl::OkStatus();
}

int64_t DescriptorCache::fetches() const {
  std::lock_guard<std::mutex> l(mu_);
  return fetches_;
}

}  // namespace gaitforge::worker
