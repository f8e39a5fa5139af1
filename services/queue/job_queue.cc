#include "services/queue/job_queue.h"

#include <algorithm>

namespace gaitforge::queue {

JobQueue::JobQueue(core::Clock& clock, QueueOptions options, uint32_t epoch)
    : clock_(clock), options_(options), epoch_(epoch) {}

void JobQueue::Add(const JobKey& key) {
  auto [it, inserted] = jobs_.try_emplace(key);
  if (!inserted) return;
  pending_.push_back(key);
}

size_t JobQueue::pending() const {
  size_t n = 0;
  for (const auto& k : pending_) {
    auto it = jobs_.find(k);
    if (it != jobs_.end() && it->second.state == State::kPending) ++n;
  }
  return n;
}

size_t JobQueue::in_flight() const {
  size_t n = 0;
  for (const auto& [k, j] : jobs_) n += j.state == State::kLeased;
  return n;
}

std::vector<Lease> JobQueue::LeaseJobs(const std::string& worker_id, int max_jobs,
                                       const std::function<bool(const JobKey&)>& accept) {
  std::vector<Lease> out;
  const int64_t now = clock_.NowMs();
  auto grant = [&](const JobKey& key, Job& job, bool backup) {
    const uint64_t id = NextLeaseId();
    job.holders.push_back(Holder{worker_id, id, now + options_.lease_ms});
    issued_[id] = Issued{key, worker_id, now};
    if (job.state == State::kPending) job.first_leased_ms = now;
    job.state = State::kLeased;
    ++counters_.leased;
    out.push_back(Lease{key, id, backup});
  };
  for (auto it = pending_.begin(); it != pending_.end() && static_cast<int>(out.size()) < max_jobs;) {
    auto j = jobs_.find(*it);
    if (j == jobs_.end() || j->second.state != State::kPending) {
      it = pending_.erase(it);
      continue;
    }
    if (!accept(*it)) {
      ++it;
      continue;
    }
    grant(*it, j->second, false);
    it = pending_.erase(it);
  }
  if (!out.empty() || options_.backup_after_ms <= 0) return out;
  // Nothing pending for this worker: back up the oldest stragglers it does not hold.
  std::vector<std::pair<int64_t, const JobKey*>> stragglers;
  for (auto& [key, job] : jobs_) {
    if (job.state != State::kLeased || job.backed_up) continue;
    if (now - job.first_leased_ms < options_.backup_after_ms) continue;
    const bool mine = std::any_of(job.holders.begin(), job.holders.end(),
                                  [&](const Holder& h) { return h.worker_id == worker_id; });
    if (mine || !accept(key)) continue;
    stragglers.emplace_back(job.first_leased_ms, &key);
  }
  std::sort(stragglers.begin(), stragglers.end());
  for (const auto& [t, key] : stragglers) {
    if (static_cast<int>(out.size()) >= max_jobs) break;
    Job& job = jobs_.at(*key);
    job.backed_up = true;
    ++counters_.backups;
    grant(*key, job, true);
  }
  return out;
}

ReportCheck JobQueue::Check(const std::string& worker_id, const JobKey& key,
                            uint64_t lease_id) const {
  auto it = jobs_.find(key);
  if (it == jobs_.end()) return ReportCheck::kUnknown;
  const Job& job = it->second;
  if (job.state == State::kDone || job.state == State::kPoisoned) return ReportCheck::kDone;
  // A lease id of another epoch was issued by a previous coordinator process: its result
  // is as good as any (results are pure functions of the job), so it may complete the job.
  if ((lease_id >> 32) != epoch_ && lease_id != 0) return ReportCheck::kOpen;
  auto lease = issued_.find(lease_id);
  if (lease == issued_.end() || lease->second.key != key || lease->second.worker_id != worker_id)
    return ReportCheck::kNotHeld;
  return ReportCheck::kOpen;
}

bool JobQueue::Complete(const JobKey& key) {
  auto it = jobs_.find(key);
  if (it == jobs_.end()) return false;
  Job& job = it->second;
  if (job.state == State::kDone || job.state == State::kPoisoned) return false;
  job.state = State::kDone;
  job.holders.clear();
  return true;
}

int JobQueue::Heartbeat(const std::string& worker_id) {
  const int64_t until = clock_.NowMs() + options_.lease_ms;
  int renewed = 0;
  for (auto& [key, job] : jobs_) {
    if (job.state != State::kLeased) continue;
    for (auto& h : job.holders) {
      if (h.worker_id == worker_id) {
        h.expires_ms = until;
        ++renewed;
      }
    }
  }
  return renewed;
}

int64_t JobQueue::LeaseAgeMs(uint64_t lease_id) const {
  auto it = issued_.find(lease_id);
  return it == issued_.end() ? -1 : clock_.NowMs() - it->second.granted_ms;
}

Expiry JobQueue::ExpireLeases() {
  Expiry out;
  const int64_t now = clock_.NowMs();
  for (auto& [key, job] : jobs_) {
    if (job.state != State::kLeased) continue;
    const size_t before = job.holders.size();
    std::erase_if(job.holders, [&](const Holder& h) { return h.expires_ms <= now; });
    const size_t expired = before - job.holders.size();
    if (expired == 0) continue;
    counters_.expired += static_cast<int64_t>(expired);
    for (size_t i = 0; i < expired; ++i) out.expired.push_back(key);
    if (!job.holders.empty()) continue;  // a backup copy is still out
    ++job.attempts;
    if (job.attempts >= options_.max_attempts) {
      job.state = State::kPoisoned;
      ++counters_.poisoned;
      out.poisoned.push_back(key);
    } else {
      job.state = State::kPending;
      ++out.requeued;
      job.backed_up = false;
      pending_.push_front(key);  // retried before newer work
    }
  }
  return out;
}

void JobQueue::RemoveStudy(const std::string& study_id) {
  std::erase_if(jobs_, [&](const auto& kv) { return kv.first.study_id == study_id; });
  std::erase_if(pending_, [&](const JobKey& k) { return k.study_id == study_id; });
}

void JobQueue::RemoveGeneration(const std::string& study_id, int generation) {
  std::erase_if(jobs_, [&](const auto& kv) {
    return kv.first.study_id == study_id && kv.first.generation == generation;
  });
  std::erase_if(pending_, [&](const JobKey& k) {
    return k.study_id == study_id && k.generation == generation;
  });
}

}  // namespace gaitforge::queue
