#pragma once
// The job queue: leases that expire, heartbeats that renew them, idempotent completion,
// poison jobs and backup copies of stragglers (../shared/guides/distributed-notes.md).
//
// Not thread-safe: the coordinator calls it under its own mutex. Time comes from an
// injected Clock so that tests can move it.
#include <compare>
#include <deque>
#include <cstdint>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "services/core/clock.h"

namespace gaitforge::queue {

struct JobKey {
  std::string study_id;
  int generation = 0;
  int member = 0;
  auto operator<=>(const JobKey&) const = default;
};

struct QueueOptions {
  // A lease ends this long after it was granted or last renewed by a heartbeat.
  int64_t lease_ms = 10000;
  // A job whose lease expired this many times is closed as poisoned.
  int max_attempts = 3;
  // Hand out a backup copy of a leased job when the queue is otherwise empty and the job
  // has been out this long, and kStragglerFactor times as long as its batch should take
  // (see set_job_ms); at most one backup per job. 0 disables backups.
  int64_t backup_after_ms = 2000;
};

struct Lease {
  JobKey key;
  uint64_t lease_id = 0;
  bool backup = false;
};

enum class ReportCheck {
  kOpen,       // the job is open and this lease may complete it
  kDone,       // already completed: a duplicate, acknowledged but not counted
  kNotHeld,    // the job is open but this worker was never leased it under this id
  kUnknown,    // no such job in the queue
};

// What one ExpireLeases call did.
struct Expiry {
  std::vector<JobKey> expired;   // one entry per lease that ran out
  std::vector<JobKey> poisoned;  // jobs closed for good
  int requeued = 0;              // jobs returned to the queue for another lease
};

struct QueueCounters {
  int64_t leased = 0;
  int64_t expired = 0;
  int64_t poisoned = 0;
  int64_t duplicates = 0;
  int64_t backups = 0;
};

class JobQueue {
 public:
  // epoch: distinguishes this coordinator process's lease ids from a previous one's.
  JobQueue(core::Clock& clock, QueueOptions options, uint32_t epoch);

  void Add(const JobKey& key);
  // Up to max_jobs pending jobs whose key `accept` allows, oldest first; when none is
  // pending, backup copies of stragglers.
  std::vector<Lease> LeaseJobs(const std::string& worker_id, int max_jobs,
                               const std::function<bool(const JobKey&)>& accept);
  ReportCheck Check(const std::string& worker_id, const JobKey& key, uint64_t lease_id) const;
  // Marks the job done; later reports are duplicates. Returns false if it was not open.
  bool Complete(const JobKey& key);
  void CountDuplicate() { ++counters_.duplicates; }
  // Renews every lease of the worker; returns how many.
  int Heartbeat(const std::string& worker_id);
  // Returns expired jobs to the queue (or closes them as poisoned).
  Expiry ExpireLeases();
  // Milliseconds since this process granted `lease_id`; -1 if it did not.
  int64_t LeaseAgeMs(uint64_t lease_id) const;
  // Forgets every job of the study (cancel, or a generation's bookkeeping when done).
  void RemoveStudy(const std::string& study_id);
  void RemoveGeneration(const std::string& study_id, int generation);

  // Both O(1): kept up to date on every change of state.
  size_t pending() const { return pending_count_; }
  size_t in_flight() const { return leased_count_; }
  // Workers holding at least one live lease.
  size_t workers_holding() const { return held_.size(); }
  bool HasJob(const JobKey& key) const { return jobs_.count(key) > 0; }
  const QueueCounters& counters() const { return counters_; }
  int64_t lease_ms() const { return options_.lease_ms; }
  void set_lease_ms(int64_t ms) { options_.lease_ms = ms; }
  int64_t backup_after_ms() const { return options_.backup_after_ms; }
  // The typical time one job takes a worker, from the workers' reports: a job leased in a
  // batch of n is a straggler once out kStragglerFactor * n times this (at least
  // backup_after_ms). A single threshold for every job backed up the last job of each
  // long batch while short batches had pulled the typical time down: the first worker
  // back then ran a needless copy and missed the next generation's start (issue 30).
  void set_job_ms(double ms) { job_ms_ = ms; }
  static constexpr double kStragglerFactor = 2.0;
  uint32_t epoch() const { return epoch_; }

 private:
  enum class State { kPending, kLeased, kDone, kPoisoned };
  struct Holder {
    std::string worker_id;
    uint64_t lease_id;
    int64_t expires_ms;
  };
  struct Job {
    State state = State::kPending;
    int attempts = 0;  // leases that expired
    int64_t first_leased_ms = 0;
    int batch = 1;  // how many jobs its lease held (the worker runs them one by one)
    bool backed_up = false;
    std::vector<Holder> holders;  // active leases
    std::vector<uint64_t> lease_ids;  // every lease id issued for it (keys of issued_)
  };
  struct Issued {
    JobKey key;
    std::string worker_id;
    int64_t granted_ms;
  };

  uint64_t NextLeaseId() { return (static_cast<uint64_t>(epoch_) << 32) | ++lease_seq_; }
  // Moves a job to `state`, keeping the counts and the straggler index in step.
  void SetState(const JobKey& key, Job& job, State state);
  // Drops a holder's entry from the per-worker index.
  void Unhold(const std::string& worker_id, const JobKey& key);
  // Drops a job from the backup candidates.
  void Unstraggle(const JobKey& key, const Job& job);
  // Up to max_jobs candidates for a backup copy to the worker, the latest first.
  std::vector<JobKey> Overdue(const std::string& worker_id, int max_jobs,
                              const std::function<bool(const JobKey&)>& accept) const;
  // Erases every trace of a job from the indexes (the job itself stays in jobs_).
  void Unindex(const JobKey& key, Job& job);
  // Forgets the matching jobs (and with forget_leases, the lease ids issued for them).
  void RemoveIf(const std::function<bool(const JobKey&)>& match, bool forget_leases);

  core::Clock& clock_;
  QueueOptions options_;
  uint32_t epoch_;
  uint32_t lease_seq_ = 0;
  std::map<JobKey, Job> jobs_;
  // Every lease id this process issued, kept after its job is gone, so that a result that
  // arrives after a cancel and resume is still recognised as held.
  std::map<uint64_t, Issued> issued_;
  // FIFO of jobs waiting for a lease. May hold keys that were completed meanwhile (a late
  // result); LeaseJobs skips those.
  std::deque<JobKey> pending_;
  QueueCounters counters_;
  // Indexes that keep every call O(log n) in the jobs involved rather than O(all jobs), so
  // that a thousand workers' leases and heartbeats stay cheap (docs/scaling.md).
  size_t pending_count_ = 0;  // jobs in kPending
  size_t leased_count_ = 0;   // jobs in kLeased
  // Leased jobs without a backup copy yet, the backup candidates: by the size of the batch
  // they were leased in, oldest lease first.
  std::map<int, std::set<std::pair<int64_t, JobKey>>> stragglers_;
  double job_ms_ = 0;
  // The jobs each worker holds a lease on (what Heartbeat renews).
  std::map<std::string, std::set<JobKey>> held_;
};

}  // namespace gaitforge::queue
