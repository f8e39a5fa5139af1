#pragma once
// The worker side of the WorkerService protocol (docs/protocol.md), as pure functions and
// small value types so that a synchronous driver (gaitforge-worker) and an asynchronous one
// (bench/swarm, a thousand emulated workers in one process) send the same bytes, retry the
// same errors and back off the same way.
#include <grpcpp/support/status.h>

#include "absl/status/status.h"

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "gaitforge/v1/worker.pb.h"

namespace gaitforge::worker {

// Lease long-poll wait and the deadlines of each call (docs/protocol.md, "Deadlines").
constexpr int kLeaseWaitMs = 2000;
constexpr double kLeaseDeadlineS = (kLeaseWaitMs + 10000) / 1000.0;
constexpr double kReportDeadlineS = 30;
constexpr double kHeartbeatDeadlineS = 5;
// A draining worker stops retrying a report after this long.
constexpr double kDrainReportGiveUpS = 10;
// The worker aims at about this much work per lease: two round trips per batch, so 0.5 s
// cost a thousand workers with 500 ms evaluations four RPCs per second each (issue 30).
constexpr double kTargetBatchSeconds = 2.0;
// A worker asks for up to this many times its target, and the coordinator hands it its
// part: the idle workers' share of what is pending, within an even part of the generation
// (Coordinator::FairShare). The headroom lets an estimate a little above the true
// evaluation time (a late timer) still take a whole part, and lets a generation of up to
// ~5 s per worker go out in one batch: with 8 jobs of 500 ms per worker and asks of 6, every
// generation took two rounds of Report and Lease, two barriers instead of one (issue 30).
constexpr double kBatchHeadroom = 2.5;

// UNAVAILABLE, DEADLINE_EXCEEDED, RESOURCE_EXHAUSTED, ABORTED, INTERNAL, UNKNOWN.
bool Retryable(const grpc::Status& s);

// What to do after a Report call.
enum class ReportFate {
  kLanded,  // accepted (or duplicates): done with the batch
  kRetry,   // transient: back off and send it again
  kDrop,    // refused for good (or too large): drop; the leases expire
};
ReportFate ClassifyReport(const grpc::Status& s);

// Exponential backoff with jitter: steps of 100 ms doubling to 5 s, each delay drawn in
// [step / 2, step].
class Backoff {
 public:
  explicit Backoff(uint32_t seed = std::random_device{}()) : rng_(seed) {}
  void Reset() { ms_ = 100; }
  // The delay to wait now; the next one doubles.
  int NextDelayMs();

 private:
  int ms_ = 100;
  std::mt19937 rng_;
};

// host-pid-xxxx.
std::string DefaultWorkerId();

v1::WorkerInfo MakeWorkerInfo(const std::string& worker_id, int threads,
                              const std::string& sim_build,
                              const std::vector<std::string>& objectives);

// Jobs to ask for: about kBatchHeadroom x kTargetBatchSeconds of work on `threads` threads given the running
// estimate of one evaluation (0: unknown, then 4 per thread), within [1, max_batch].
int WantJobs(int threads, double mean_eval_s, int max_batch);
// The running estimate after a batch of n evaluations took batch_s on `threads` threads.
double UpdateMeanEval(double mean_eval_s, double batch_s, int threads, int n);

v1::LeaseRequest MakeLeaseRequest(const v1::WorkerInfo& info, int want);
v1::HeartbeatRequest MakeHeartbeatRequest(const v1::WorkerInfo& info);
// How often a worker holding a batch heartbeats: max(200 ms, lease_ms / 3).
int HeartbeatIntervalMs(int lease_ms);

// Copies each job's objective and bounds in from its study's context in the lease
// (LeaseResponse.studies); an error names a job whose study has no context there.
absl::Status ExpandLease(v1::LeaseResponse& lease);

// A report with one result per leased job, in lease order: key and lease id set, the
// evaluation left for FillResult.
v1::ReportRequest StartReport(const v1::WorkerInfo& info, const v1::LeaseResponse& lease);

}  // namespace gaitforge::worker
