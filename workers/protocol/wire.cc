#include "workers/protocol/wire.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"

namespace gaitforge::worker {

bool Retryable(const grpc::Status& s) {
  switch (s.error_code()) {
    case grpc::StatusCode::UNAVAILABLE:
    case grpc::StatusCode::DEADLINE_EXCEEDED:
    case grpc::StatusCode::RESOURCE_EXHAUSTED:
    case grpc::StatusCode::ABORTED:
    case grpc::StatusCode::INTERNAL:
    case grpc::StatusCode::UNKNOWN:
      return true;
    default:
      return false;
  }
}

ReportFate ClassifyReport(const grpc::Status& s) {
  if (s.ok()) return ReportFate::kLanded;
  // A report over the message limit would fail again: drop it like a refusal.
  if (!Retryable(s) || s.error_code() == grpc::StatusCode::RESOURCE_EXHAUSTED)
    return ReportFate::kDrop;
  return ReportFate::kRetry;
}

int Backoff::NextDelayMs() {
  std::uniform_int_distribution<int> jitter(ms_ / 2, ms_);
  const int delay = jitter(rng_);
  ms_ = std::min(ms_ * 2, 5000);
  return delay;
}

std::string DefaultWorkerId() {
  char host[256] = {0};
  gethostname(host, sizeof host - 1);
  std::random_device rd;
  return absl::StrCat(host, "-", getpid(), "-", absl::Hex(rd() & 0xffff, absl::kZeroPad4));
}

v1::WorkerInfo MakeWorkerInfo(const std::string& worker_id, int threads,
                              const std::string& sim_build,
                              const std::vector<std::string>& objectives) {
  v1::WorkerInfo info;
  info.set_worker_id(worker_id.empty() ? DefaultWorkerId() : worker_id);
  char host[256] = {0};
  gethostname(host, sizeof host - 1);
  info.set_hostname(host);
  info.set_threads(threads);
  info.set_sim_build(sim_build);
  for (const auto& n : objectives) info.add_objectives(n);
  return info;
}

int WantJobs(int threads, double mean_eval_s, int max_batch) {
  int want = threads * 4;
  if (mean_eval_s > 0) {
    const double per_thread = std::ceil(kBatchHeadroom * kTargetBatchSeconds / mean_eval_s);
    want = static_cast<int>(std::min<double>(threads * per_thread, 1 << 20));
  }
  return std::clamp(want, 1, std::min(max_batch, 1024));
}

double UpdateMeanEval(double mean_eval_s, double batch_s, int threads, int n) {
  const double per_eval = batch_s * threads / std::max(n, 1);
  return mean_eval_s == 0 ? per_eval : 0.7 * mean_eval_s + 0.3 * per_eval;
}

v1::LeaseRequest MakeLeaseRequest(const v1::WorkerInfo& info, int want) {
  v1::LeaseRequest req;
  *req.mutable_worker() = info;
  req.set_max_jobs(std::clamp(want, 1, 1024));
  req.set_wait_ms(kLeaseWaitMs);
  return req;
}

v1::HeartbeatRequest MakeHeartbeatRequest(const v1::WorkerInfo& info) {
  v1::HeartbeatRequest req;
  *req.mutable_worker() = info;
  return req;
}

int HeartbeatIntervalMs(int lease_ms) { return std::max(200, lease_ms / 3); }

absl::Status ExpandLease(v1::LeaseResponse& lease) {
  for (v1::Job& job : *lease.mutable_jobs()) {
    if (job.has_objective()) continue;  // sent whole
    const v1::StudyContext* ctx = nullptr;
    for (const auto& c : lease.studies())
      if (c.study_id() == job.key().study_id()) ctx = &c;
    if (!ctx)
      return absl::DataLossError(absl::StrCat(
          "lease: job (study '", job.key().study_id(), "', generation ", job.key().generation(),
          ", member ", job.key().member(), ") has no objective and its study has no context"));
    *job.mutable_objective() = ctx->objective();
    *job.mutable_bounds() = ctx->bounds();
  }
  return absl::OkStatus();
}

v1::ReportRequest StartReport(const v1::WorkerInfo& info, const v1::LeaseResponse& lease) {
  v1::ReportRequest report;
  *report.mutable_worker() = info;
  for (const auto& job : lease.jobs()) {
    v1::JobResult* out = report.add_results();
    *out->mutable_key() = job.key();
    out->set_lease_id(job.lease_id());
  }
  return report;
}

}  // namespace gaitforge::worker
