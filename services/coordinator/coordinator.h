#pragma once
// The coordinator's domain logic: a study is an engine + the job queue + the store.
//
// Flow of one generation: Ask() -> jobs in the queue -> workers Lease/Report -> when every
// member has a result, Tell() (evaluations sorted by member) -> one store transaction with
// the generation, engine state and hall of fame -> the next Ask().
// Thread-safe: every public method takes mu_. The gRPC adapters (services.h) only
// convert messages and statuses.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <future>
#include <list>
#include <set>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include "absl/status/statusor.h"
#include "gaitforge/v1/study.pb.h"
#include "gaitforge/v1/worker.pb.h"
#include "services/coordinator/recordings.h"
#include "services/core/clock.h"
#include "services/engines/engine.h"
#include "services/queue/job_queue.h"
#include "storage/study_store.h"

namespace gaitforge::coordinator {

class Metrics;

struct CoordinatorOptions {
  // Lease length; a heartbeat renews it. Default 10 s.
  int64_t lease_ms = 10000;
  // Leases a job may lose (expire) before it is closed as poisoned.
  int max_attempts = 3;
  // Backup copies of stragglers after this long (0: never).
  int64_t backup_after_ms = 2000;
  // Serve reads only: do not resume running studies, refuse new ones.
  bool read_only = false;
  // Shown in StudySummary.db_path.
  std::string db_path;
  // Prometheus metrics to update (optional; not owned).
  class Metrics* metrics = nullptr;
  // Largest recording accepted (CSV + sidecar), bytes.
  size_t max_recording_bytes = 64u << 20;
};

// A new id for a study or a diagnosis: its name as a slug (at most 32 characters) and six
// random hex digits.
std::string NewId(const std::string& name);

// OK if a worker call's identity is usable (an id of 1..256 characters).
absl::Status CheckWorker(const v1::WorkerInfo& w);

class Coordinator {
 public:
  Coordinator(std::unique_ptr<storage::StudyStore> store, CoordinatorOptions options,
              core::Clock& clock);
  ~Coordinator();
  Coordinator(const Coordinator&) = delete;
  Coordinator& operator=(const Coordinator&) = delete;

  // Resumes every study the database says is running (after a restart).
  absl::Status RecoverStudies();

  // StudyService.
  absl::StatusOr<v1::StudySummary> CreateStudy(v1::StudySpec spec);
  absl::StatusOr<v1::StudySummary> GetStudy(const std::string& id);
  absl::StatusOr<std::vector<v1::StudySummary>> ListStudies();
  absl::StatusOr<v1::StudySummary> ResumeStudy(const std::string& id);
  absl::StatusOr<v1::StudySummary> CancelStudy(const std::string& id);
  absl::StatusOr<v1::GetHallOfFameResponse> HallOfFame(const std::string& id,
                                                       std::optional<int> generation);
  absl::StatusOr<v1::GetHistoryResponse> History(const std::string& id);
  absl::StatusOr<v1::ListIndividualsResponse> Individuals(const std::string& id, int generation);
  // Current progress and a version that changes with every commit or state change.
  absl::StatusOr<std::pair<v1::Progress, int64_t>> Progress(const std::string& id);
  // Waits until every write accepted so far is committed to the database.
  absl::Status Flush();
  // Blocks until the version differs from `seen`, or timeout. Returns the new version.
  int64_t WaitForChange(int64_t seen, int timeout_ms);

  // WorkerService.
  // A lease's answer, delivered exactly once: on the calling thread when jobs are there
  // (or the call waits for none), else on the lease dispatcher's thread when jobs arrive,
  // `wait_ms` passes, `cancelled` turns true or the coordinator shuts down. A thousand
  // waiting long polls cost no thread each, and a new generation is handed to all of them
  // from one place (issue 30).
  using LeaseDone = std::function<void(absl::StatusOr<v1::LeaseResponse>)>;
  void LeaseAsync(const v1::LeaseRequest& request, LeaseDone done,
                  std::shared_ptr<std::atomic<bool>> cancelled = nullptr);
  // The same, blocking until the answer.
  absl::StatusOr<v1::LeaseResponse> Lease(const v1::LeaseRequest& request);
  // Re-examines the waiting leases now (a caller cancelled one).
  void WakeLeases();
  absl::StatusOr<v1::ReportResponse> Report(const v1::ReportRequest& request);
  absl::StatusOr<v1::HeartbeatResponse> Heartbeat(const v1::HeartbeatRequest& request);
  // The robot descriptor a leased job names by content hash (objective.robot_descriptor_hash).
  absl::StatusOr<v1::GetRobotResponse> GetRobot(const v1::GetRobotRequest& req);

  // Expires leases, closes poisoned jobs, surfaces storage failures. Called periodically.
  void Tick();
  // Wakes long polls; waits for every write.
  void Shutdown();

  queue::QueueCounters QueueStats();
  Recordings& recordings() { return *recordings_; }
  storage::StudyStore& store() { return *store_; }

 private:
  struct Result {
    v1::Evaluation evaluation;
    std::string worker_id;
    double eval_seconds = 0;
    bool carried = false;
    double violation = 0;  // total constraint violation
  };
  struct Study {
    std::string id;
    storage::StudyRecord record;  // live copy of the studies row
    v1::StudySpec spec;
    std::unique_ptr<engines::Engine> engine;
    std::vector<std::optional<Result>> results;  // current generation, by member
    int remaining = 0;
    int64_t evaluations = 0;  // distinct evaluated jobs, all generations
    std::deque<std::pair<int64_t, int64_t>> rate;  // (ms, evaluations) samples
    storage::JobCounters counters;                  // current generation's
    int last_invalid = 0;             // invalid members of the latest committed generation
    std::string last_invalid_reason;  // and their commonest reason
    // The study's objective and bounds, sent once per lease (built at the first lease;
    // immutable, so it is copied outside mu_).
    std::shared_ptr<const v1::StudyContext> context;
    // The current generation's jobs each worker has leased (cleared when the generation
    // changes), for the cap on a worker's part of a generation (PartLeft).
    int part_generation = -1;
    std::unordered_map<std::string, int> leased_by_worker;
  };

  // A Lease call waiting for jobs.
  struct Waiter {
    std::string worker_id, build;
    std::set<std::string> objectives;  // empty: any
    int max_jobs = 1;
    std::chrono::steady_clock::time_point deadline;
    LeaseDone done;
    std::shared_ptr<std::atomic<bool>> cancelled;  // may be null
  };
  // What a lease grants, decided under mu_ and turned into a message outside it.
  struct Granted {
    queue::Lease lease;
    std::shared_ptr<const v1::StudyContext> context;  // the study's objective and bounds
    std::vector<double> genes;
  };
  struct Delivery {
    LeaseDone done;
    absl::Status error;
    std::vector<Granted> granted = {};
    int64_t lease_ms = 0;
  };
  // The waiter's answer if it has one now; `final`: answer even with no jobs.
  std::optional<Delivery> TryServe(Waiter& w, bool final);  // under mu_
  std::vector<Granted> Grant(const std::vector<queue::Lease>& leases, const std::string& worker_id,
                             const std::string& build);
  static void Deliver(Delivery d);  // outside mu_
  // Delivers `ready` with mu_ released (held by `l` before and after), and clears it.
  void DeliverUnlocked(std::unique_lock<std::mutex>& l, std::vector<Delivery>& ready);
  void DispatchLeases();            // the dispatcher thread's loop
  void WakeDispatcher();            // under mu_

  absl::StatusOr<std::unique_ptr<engines::Engine>> MakeEngine(const v1::StudySpec& spec);
  // The engine's spread after `generation` if that is the latest committed one.
  std::vector<double> SpreadAfter(const std::string& id, int generation);
  // Why a completed study stopped ("" for other states), from its spec and its engine
  // rebuilt from the latest stored state. Not under mu_.
  std::string StopReason(const storage::StudyRecord& r);
  // Loads a study's engine from its last committed generation and schedules its jobs.
  absl::Status Activate(const storage::StudyRecord& record);
  void StartGeneration(Study& s, const std::vector<storage::IndividualRecord>& stored);
  void CompleteGeneration(Study& s);
  void Accept(Study& s, int member, Result result, std::vector<storage::IndividualRecord>* out);
  v1::StudySummary Summarize(const storage::StudyRecord& r) const;
  v1::Progress MakeProgress(const Study* s, const storage::StudyRecord& r) const;
  absl::StatusOr<storage::StudyRecord> Record(const std::string& id);  // memory, else store
  storage::StudyRecord LiveRecord(const Study& s) const;
  void SetState(Study& s, const std::string& state, const std::string& error);
  void Bump();
  int FairShare(const std::string& worker_id, int requested);
  // Jobs `worker_id` may still lease of the running studies' current generations: an even
  // part of them among the active workers, less what it already holds of them; at least 1.
  int64_t PartLeft(const std::string& worker_id, int64_t active);
  // Records a call from the worker (Lease, Report, Heartbeat).
  void Touch(const std::string& worker_id);
  // Workers seen within one lease period (at least as fresh as kActiveRecountMs).
  int64_t ActiveWorkers();
  // The engine is done, or the spec's generation count is reached.
  static bool Finished(const Study& s);
  void WatchWrite(std::future<absl::Status> f, const std::string& study_id);

  std::unique_ptr<storage::StudyStore> store_;
  const CoordinatorOptions options_;
  std::unique_ptr<Recordings> recordings_;
  core::Clock& clock_;

  mutable std::mutex mu_;
  std::condition_variable work_cv_;    // wakes the lease dispatcher
  std::condition_variable change_cv_;  // version_ changed
  // Studies this process scheduled, running or ended since; their record is authoritative
  // (the store may lag by the writes in flight). Jobs are only scheduled for running ones.
  std::map<std::string, std::unique_ptr<Study>> studies_;  // GUARDED_BY(mu_)
  // Robot descriptors of the jobs leased, by content hash; jobs carry only the hash.
  std::map<std::string, std::string> robot_texts_;  // GUARDED_BY(mu_)
  queue::JobQueue queue_;                                  // GUARDED_BY(mu_)
  std::map<std::string, int64_t> workers_seen_;            // GUARDED_BY(mu_)
  int64_t active_ = 0, active_at_ms_ = -1;  // cached ActiveWorkers() and when; GUARDED_BY(mu_)
  std::vector<std::pair<std::string, std::future<absl::Status>>> writes_;  // GUARDED_BY(mu_)
  int64_t version_ = 0;                                    // GUARDED_BY(mu_)
  // Smoothed time from lease to report of a batch; leases last 5x this (at least
  // options_.lease_ms).
  double batch_ms_ewma_ = 0;                               // GUARDED_BY(mu_)
  // Smoothed time one job takes a worker (its reported eval_seconds): the queue's measure
  // of a straggler (JobQueue::set_job_ms).
  double job_ms_ewma_ = 0;                                 // GUARDED_BY(mu_)
  bool shutdown_ = false;                                  // GUARDED_BY(mu_)
  std::list<Waiter> waiters_;                              // GUARDED_BY(mu_)
  bool wake_ = false;         // jobs may be there for waiters; GUARDED_BY(mu_)
  // A waiter's call was cancelled, or one waits less than the dispatcher would sleep:
  // answer what is due and sleep again; GUARDED_BY(mu_).
  bool recheck_ = false;
  // When the dispatcher wakes at the latest; GUARDED_BY(mu_).
  std::chrono::steady_clock::time_point next_deadline_;
  std::thread dispatcher_;  // last member: started when everything else is built
};

}  // namespace gaitforge::coordinator
