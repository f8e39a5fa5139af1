#include "services/queue/job_queue.h"

#include <algorithm>

namespace gaitforge::queue {

JobQueue::JobQueue(core::Clock& clock, QueueOptions options, uint32_t epoch)
    : clock_(clock), options_(options), epoch_(epoch) {}

void JobQueue::SetState(const JobKey& key, Job& job, State state) {
  if (job.state == State::kPending) --pending_count_;
  if (job.state == State::kLeased) {
    --leased_count_;
    if (!job.backed_up) Unstraggle(key, job);
  }
  job.state = state;
  if (state == State::kPending) ++pending_count_;
  if (state == State::kLeased) {
    ++leased_count_;
    if (!job.backed_up) stragglers_[job.batch].insert({job.first_leased_ms, key});
  }
}

void JobQueue::Unhold(const std::string& worker_id, const JobKey& key) {
  auto it = held_.find(worker_id);
  if (it == held_.end()) return;
  it->second.erase(key);
  if (it->second.empty()) held_.erase(it);
}

void JobQueue::Unindex(const JobKey& key, Job& job) {
  for (const auto& h : job.holders) Unhold(h.worker_id, key);
  job.holders.clear();
  SetState(key, job, State::kDone);
}

void JobQueue::Add(const JobKey& key) {
  auto [it, inserted] = jobs_.try_emplace(key);
  if (!inserted) return;
  ++pending_count_;  // a new Job starts in kPending
  pending_.push_back(key);
}

std::vector<Lease> JobQueue::LeaseJobs(const std::string& worker_id, int max_jobs,
                                       const std::function<bool(const JobKey&)>& accept) {
  std::vector<Lease> out;
  std::vector<JobKey> batch;
  const int64_t now = clock_.NowMs();
  auto grant = [&](const JobKey& key, Job& job, bool backup) {
    const uint64_t id = NextLeaseId();
    job.holders.push_back(Holder{worker_id, id, now + options_.lease_ms});
    job.lease_ids.push_back(id);
    held_[worker_id].insert(key);
    issued_[id] = Issued{key, worker_id, now};
    if (job.state == State::kPending) {
      job.first_leased_ms = now;
      job.batch = static_cast<int>(batch.size());
      SetState(key, job, State::kLeased);
    }
    ++counters_.leased;
    out.push_back(Lease{key, id, backup});
  };
  for (auto it = pending_.begin(); it != pending_.end() && static_cast<int>(batch.size()) < max_jobs;) {
    auto j = jobs_.find(*it);
    if (j == jobs_.end() || j->second.state != State::kPending) {
      it = pending_.erase(it);
      continue;
    }
    if (!accept(*it)) {
      ++it;
      continue;
    }
    batch.push_back(*it);
    it = pending_.erase(it);
  }
  for (const auto& key : batch) grant(key, jobs_.at(key), false);
  if (!out.empty() || options_.backup_after_ms <= 0) return out;
  // Nothing pending for this worker: back up the longest overdue stragglers it does not hold.
  for (const auto& key : Overdue(worker_id, max_jobs, accept)) {
    Job& job = jobs_.at(key);
    Unstraggle(key, job);
    job.backed_up = true;
    ++counters_.backups;
    grant(key, job, true);
  }
  return out;
}

void JobQueue::Unstraggle(const JobKey& key, const Job& job) {
  auto group = stragglers_.find(job.batch);
  if (group == stragglers_.end()) return;
  group->second.erase({job.first_leased_ms, key});
  if (group->second.empty()) stragglers_.erase(group);
}

std::vector<JobKey> JobQueue::Overdue(const std::string& worker_id, int max_jobs,
                                      const std::function<bool(const JobKey&)>& accept) const {
  const int64_t now = clock_.NowMs();
  std::vector<std::pair<int64_t, JobKey>> late;  // (how late, job)
  for (const auto& [batch, jobs] : stragglers_) {
    const int64_t after = std::max<int64_t>(
        options_.backup_after_ms,
        static_cast<int64_t>(kStragglerFactor * job_ms_ * static_cast<double>(batch)));
    int taken = 0;
    for (const auto& [first_ms, key] : jobs) {  // oldest first: stop at the first in time
      if (taken >= max_jobs || now - first_ms < after) break;
      const Job& job = jobs_.at(key);
      const bool mine = std::any_of(job.holders.begin(), job.holders.end(),
                                    [&](const Holder& h) { return h.worker_id == worker_id; });
      if (mine || !accept(key)) continue;
      late.push_back({now - first_ms - after, key});
      ++taken;
    }
  }
  std::sort(late.begin(), late.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first > b.first : a.second < b.second;  // latest, then by key
  });
  std::vector<JobKey> out;
  for (size_t i = 0; i < late.size() && static_cast<int>(i) < max_jobs; ++i)
    out.push_back(late[i].second);
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
  Unindex(key, job);
  return true;
}

int JobQueue::Heartbeat(const std::string& worker_id) {
  auto held = held_.find(worker_id);
  if (held == held_.end()) return 0;
  const int64_t until = clock_.NowMs() + options_.lease_ms;
  int renewed = 0;
  for (const auto& key : held->second) {
    for (auto& h : jobs_.at(key).holders) {
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
    std::erase_if(job.holders, [&](const Holder& h) {
      if (h.expires_ms > now) return false;
      Unhold(h.worker_id, key);
      return true;
    });
    const size_t expired = before - job.holders.size();
    if (expired == 0) continue;
    counters_.expired += static_cast<int64_t>(expired);
    for (size_t i = 0; i < expired; ++i) out.expired.push_back(key);
    if (!job.holders.empty()) continue;  // a backup copy is still out
    ++job.attempts;
    if (job.attempts >= options_.max_attempts) {
      SetState(key, job, State::kPoisoned);
      ++counters_.poisoned;
      out.poisoned.push_back(key);
    } else {
      SetState(key, job, State::kPending);
      ++out.requeued;
      job.backed_up = false;
      pending_.push_front(key);  // retried before newer work
    }
  }
  return out;
}

void JobQueue::RemoveStudy(const std::string& study_id) {
  RemoveIf([&](const JobKey& k) { return k.study_id == study_id; }, false);
}

void JobQueue::RemoveGeneration(const std::string& study_id, int generation) {
  // A committed generation's late results are duplicates by their generation alone (the
  // coordinator checks that first), so its lease ids need not be remembered.
  RemoveIf([&](const JobKey& k) { return k.study_id == study_id && k.generation == generation; },
           true);
}

void JobQueue::RemoveIf(const std::function<bool(const JobKey&)>& match, bool forget_leases) {
  for (auto it = jobs_.begin(); it != jobs_.end();) {
    if (!match(it->first)) {
      ++it;
      continue;
    }
    Unindex(it->first, it->second);
    if (forget_leases)
      for (uint64_t id : it->second.lease_ids) issued_.erase(id);
    it = jobs_.erase(it);
  }
  std::erase_if(pending_, match);
}

}  // namespace gaitforge::queue
