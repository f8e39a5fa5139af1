#include "workers/worker/worker_loop.h"

#include <grpcpp/grpcpp.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <fstream>
#include <map>
#include <random>
#include <thread>

#include "absl/strings/str_cat.h"
#include "gaitforge/v1/recording.grpc.pb.h"
#include "gaitforge/v1/worker.grpc.pb.h"
#include "services/core/build_info.h"
#include "services/rpc/channel.h"
#include "workers/protocol/descriptor_cache.h"
#include "workers/protocol/job_eval.h"
#include "workers/protocol/wire.h"
#include "workers/worker/batch_runner.h"
#include "robots/registry.h"
#include "workers/worker/recording_cache.h"

namespace gaitforge::worker {
namespace {

using Clock = std::chrono::steady_clock;

// host:port from a file written by the coordinator (--address-file); empty until it exists.
std::string ReadAddressFile(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
  return line;
}

// Sleeps the backoff's next delay in 20 ms steps, returning early once `drain` is set.
void SleepBackoff(Backoff& backoff, std::atomic<bool>& drain) {
  const auto until = Clock::now() + std::chrono::milliseconds(backoff.NextDelayMs());
  while (Clock::now() < until && !drain.load())
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
}

using Fetched = std::map<std::string, absl::StatusOr<std::shared_ptr<const recording::Recording>>>;

// One worker process's loop, its connection and its heartbeat thread.
class WorkerLoop {
 public:
  WorkerLoop(const WorkerOptions& o, const objectives::ObjectiveRegistry& registry,
             std::atomic<bool>& drain)
      : o_(o),
        registry_(registry),
        drain_(drain),
        copts_{o.coordinator, o.tls_ca, o.tls_cert, o.tls_key, o.token},
        recordings_([this](const std::string& hash) { return FetchRecording(hash); }),
        descriptors_([this](const std::string& hash) { return FetchDescriptor(hash); }),
        runner_(o.threads) {}

  int Run(WorkerStats* stats_out);

 private:
  enum class Leased { kJobs, kNone, kRetry, kStop };
  // Waits for the address file if there is one, then opens the channel; false: exit 2.
  bool Connect(bool& drained);
  void SetStubs(const std::shared_ptr<grpc::Channel>& channel);
  std::shared_ptr<v1::WorkerService::Stub> Stub();
  // After a failed call: a restarted coordinator may have moved (another node).
  void FollowCoordinator();
  absl::StatusOr<RecordingCache::Bytes> FetchRecording(const std::string& hash);
  absl::StatusOr<std::string> FetchDescriptor(const std::string& hash);
  void HeartbeatLoop();
  Leased Lease(v1::LeaseResponse& lease);
  void SetLeaseCall(grpc::ClientContext* ctx);
  // A lease's jobs made whole (each study's context copied in) and its period noted;
  // false (exit 3) when a job has no context.
  bool TakeLease(v1::LeaseResponse& lease);
  // The recordings the batch names, fetched before evaluating so that a transient network
  // error delays the batch rather than changing its results; false when draining left
  // some unfetched.
  bool FetchRecordings(const v1::LeaseResponse& lease, Fetched& fetched);
  // The robot descriptors the batch names by hash, put back into its jobs; false when
  // draining left one unfetched, or the coordinator refuses it for good (then the batch
  // is dropped and its leases expire).
  bool FillDescriptors(v1::LeaseResponse& lease);
  v1::ReportRequest Evaluate(const v1::LeaseResponse& lease, const Fetched& fetched);
  // Reports until it lands; a draining worker gives up after about 10 s. Unless draining,
  // the call also asks for the next batch (ReportRequest.next: one round trip per batch);
  // the jobs it brings go to *next. A drain cancels that wait, and the report goes again
  // without it (a duplicate if it had landed).
  void SendReport(v1::ReportRequest report, v1::LeaseResponse* next);

  const WorkerOptions& o_;
  const objectives::ObjectiveRegistry& registry_;
  std::atomic<bool>& drain_;
  rpc::ChannelOptions copts_;
  std::mutex stub_mu_;  // guards the stubs (replaced when the coordinator moves)
  std::shared_ptr<v1::WorkerService::Stub> stub_;
  std::shared_ptr<v1::RecordingService::Stub> recordings_stub_;
  RecordingCache recordings_;
  DescriptorCache descriptors_;
  BatchRunner runner_;
  v1::WorkerInfo info_;
  std::atomic<int> lease_ms_{10000};
  std::atomic<bool> holding_{false}, stop_heartbeat_{false};
  // Draining, and the coordinator stopped answering heartbeats: nobody would take the
  // batch's results, so its unstarted jobs are skipped and it is not reported (its leases
  // expire on a restarted coordinator). Set by the heartbeat thread.
  std::atomic<bool> orphaned_{false};
  std::mutex lease_mu_;
  // The pending call that waits for jobs (a Lease, or a Report asking for the next
  // batch), which a drain cancels; guarded by lease_mu_.
  grpc::ClientContext* lease_ctx_ = nullptr;
  Backoff backoff_;
  double mean_eval_s_ = 0.0;  // running estimate of one evaluation's time
  int code_ = 0;
  WorkerStats stats_;
};

bool WorkerLoop::Connect(bool& drained) {
  if (!o_.coordinator_file.empty()) {
    // Wait for the coordinator to publish its address (Slurm: it may start after us).
    while ((copts_.target = ReadAddressFile(o_.coordinator_file)).empty()) {
      if ((drained = drain_.load())) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
    }
  }
  auto channel = rpc::MakeChannel(copts_);
  if (!channel.ok()) {
    spdlog::error("{}", std::string(channel.status().message()));
    return false;
  }
  SetStubs(*channel);
  return true;
}

void WorkerLoop::SetStubs(const std::shared_ptr<grpc::Channel>& channel) {
  std::lock_guard<std::mutex> l(stub_mu_);
  stub_ = v1::WorkerService::NewStub(channel);
  recordings_stub_ = v1::RecordingService::NewStub(channel);
}

std::shared_ptr<v1::WorkerService::Stub> WorkerLoop::Stub() {
  std::lock_guard<std::mutex> l(stub_mu_);
  return stub_;
}

void WorkerLoop::FollowCoordinator() {
  if (o_.coordinator_file.empty()) return;
  const std::string target = ReadAddressFile(o_.coordinator_file);
  if (target.empty() || target == copts_.target) return;
  copts_.target = target;
  if (auto ch = rpc::MakeChannel(copts_); ch.ok()) {
    SetStubs(*ch);
    spdlog::info("worker={} following the coordinator to {}", info_.worker_id(), target);
  }
}

absl::StatusOr<RecordingCache::Bytes> WorkerLoop::FetchRecording(const std::string& hash) {
  std::shared_ptr<v1::RecordingService::Stub> rs;
  {
    std::lock_guard<std::mutex> l(stub_mu_);
    rs = recordings_stub_;
  }
  grpc::ClientContext ctx;
  rpc::PrepareCall(ctx, 60, o_.token);
  v1::GetRecordingRequest req;
  req.set_hash(hash);
  v1::GetRecordingResponse resp;
  grpc::Status s = rs->GetRecording(&ctx, req, &resp);
  if (!s.ok())
    return absl::Status(static_cast<absl::StatusCode>(s.error_code()), s.error_message());
  return RecordingCache::Bytes{resp.recording().name(), resp.csv(), resp.sidecar()};
}

absl::StatusOr<std::string> WorkerLoop::FetchDescriptor(const std::string& hash) {
  grpc::ClientContext ctx;
  rpc::PrepareCall(ctx, 60, o_.token);
  v1::GetRobotRequest req;
  req.set_hash(hash);
  v1::GetRobotResponse resp;
  grpc::Status s = Stub()->GetRobot(&ctx, req, &resp);
  if (!s.ok())
    return absl::Status(static_cast<absl::StatusCode>(s.error_code()), s.error_message());
  return resp.text();
}

bool WorkerLoop::FillDescriptors(v1::LeaseResponse& lease) {
  for (;;) {
    const absl::Status s = descriptors_.Fill(lease);
    if (s.ok()) return true;
    const grpc::Status g(static_cast<grpc::StatusCode>(s.code()), std::string(s.message()));
    if (!Retryable(g) && s.code() != absl::StatusCode::kDataLoss) {
      spdlog::error("worker={} robot descriptor refused: {}; the batch is dropped",
                    info_.worker_id(), std::string(s.message()));
      return false;
    }
    if (drain_.load()) return false;
    spdlog::warn("worker={} fetching a robot descriptor: {}; retrying", info_.worker_id(),
                 std::string(s.message()));
    SleepBackoff(backoff_, drain_);
  }
}

// Heartbeats from their own thread, so a long evaluation never loses its lease; the same
// thread cancels a pending long-poll Lease as soon as a drain is requested.
void WorkerLoop::HeartbeatLoop() {
  auto last = Clock::now();
  bool drain_seen = false;
  while (!stop_heartbeat_.load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const bool draining = drain_.load();
    if (draining) {
      std::lock_guard<std::mutex> l(lease_mu_);
      if (lease_ctx_) lease_ctx_->TryCancel();
    }
    const bool now = draining && !drain_seen;  // a drain checks the coordinator at once
    drain_seen = draining;
    if (!now &&
        Clock::now() - last < std::chrono::milliseconds(HeartbeatIntervalMs(lease_ms_.load())))
      continue;
    last = Clock::now();
    if (!holding_.load()) continue;
    grpc::ClientContext ctx;
    rpc::PrepareCall(ctx, kHeartbeatDeadlineS, o_.token);
    const v1::HeartbeatRequest req = MakeHeartbeatRequest(info_);
    v1::HeartbeatResponse resp;
    grpc::Status s = Stub()->Heartbeat(&ctx, req, &resp);
    if (s.ok()) lease_ms_ = resp.lease_ms();
    else spdlog::debug("heartbeat failed: {}", s.error_message());
    const bool gone = s.error_code() == grpc::StatusCode::UNAVAILABLE ||
                      s.error_code() == grpc::StatusCode::DEADLINE_EXCEEDED;
    if (draining && gone && !orphaned_.exchange(true))
      spdlog::warn(
          "worker={} draining and the coordinator is gone ({}): the batch in hand is "
          "abandoned",
          info_.worker_id(), s.error_message());
  }
}

WorkerLoop::Leased WorkerLoop::Lease(v1::LeaseResponse& lease) {
  const v1::LeaseRequest lreq =
      MakeLeaseRequest(info_, WantJobs(o_.threads, mean_eval_s_, o_.max_batch));
  grpc::ClientContext ctx;
  rpc::PrepareCall(ctx, kLeaseDeadlineS, o_.token);
  SetLeaseCall(&ctx);
  grpc::Status s = Stub()->Lease(&ctx, lreq, &lease);
  SetLeaseCall(nullptr);
  if (drain_.load() && s.error_code() == grpc::StatusCode::CANCELLED) return Leased::kStop;
  if (!s.ok()) {
    if (!Retryable(s)) {
      spdlog::error("lease refused: {} ({})", s.error_message(), static_cast<int>(s.error_code()));
      code_ = 3;
      return Leased::kStop;
    }
    spdlog::warn("coordinator unreachable ({}); retrying", s.error_message());
    SleepBackoff(backoff_, drain_);
    FollowCoordinator();
    return Leased::kRetry;
  }
  backoff_.Reset();
  if (!TakeLease(lease)) return Leased::kStop;
  return lease.jobs_size() == 0 ? Leased::kNone : Leased::kJobs;
}

bool WorkerLoop::TakeLease(v1::LeaseResponse& lease) {
  if (auto e = ExpandLease(lease); !e.ok()) {
    spdlog::error("{}", std::string(e.message()));
    code_ = 3;
    return false;
  }
  lease_ms_ = lease.lease_ms();
  return true;
}

bool WorkerLoop::FetchRecordings(const v1::LeaseResponse& lease, Fetched& fetched) {
  for (const auto& job : lease.jobs()) {
    // A robot the study carries may be the one its recordings name.
    std::shared_ptr<const robots::RobotDescriptor> robot;
    if (!job.objective().robot_descriptor().empty()) {
      auto resolved =
          robots::ResolveRobot(job.objective().robot(), job.objective().robot_descriptor());
      if (resolved.ok()) robot = *resolved;  // else the objective says why
    }
    for (const auto& hash : job.objective().recordings()) {
      if (fetched.count(hash)) continue;
      for (;;) {
        auto r = recordings_.Get(hash, robot.get());
        const grpc::StatusCode code = static_cast<grpc::StatusCode>(r.status().code());
        const bool transient = !r.ok() && code != grpc::StatusCode::RESOURCE_EXHAUSTED &&
                               Retryable(grpc::Status(code, std::string(r.status().message())));
        if (!transient) {
          fetched.emplace(hash, std::move(r));
          break;
        }
        if (drain_.load()) return false;  // leave the batch unevaluated: its leases expire
        spdlog::warn("worker={} fetching recording {}: {}; retrying", info_.worker_id(), hash,
                     std::string(r.status().message()));
        SleepBackoff(backoff_, drain_);
      }
    }
  }
  return true;
}

v1::ReportRequest WorkerLoop::Evaluate(const v1::LeaseResponse& lease, const Fetched& fetched) {
  const int n = lease.jobs_size();
  v1::ReportRequest report = StartReport(info_, lease);
  const auto t0 = Clock::now();
  std::atomic<int> skipped{0};
  runner_.Run(n, [&](int i) {
    if (orphaned_.load()) {
      ++skipped;
      return;
    }
    const auto start = Clock::now();
    const objectives::EvalResult r = EvaluateJob(registry_, lease.jobs(i), fetched);
    FillResult(report.mutable_results(i), r,
               std::chrono::duration<double>(Clock::now() - start).count());
  });
  if (orphaned_.load()) {
    spdlog::warn("worker={} left {} of {} jobs unevaluated and reports none: their leases expire",
                 info_.worker_id(), skipped.load(), n);
    return report;
  }
  const double batch_s = std::chrono::duration<double>(Clock::now() - t0).count();
  mean_eval_s_ = UpdateMeanEval(mean_eval_s_, batch_s, o_.threads, n);
  stats_.evaluated += n;
  return report;
}

void WorkerLoop::SendReport(v1::ReportRequest report, v1::LeaseResponse* next) {
  const int n = report.results_size();
  const auto give_up =
      Clock::now() + std::chrono::milliseconds(static_cast<int>(kDrainReportGiveUpS * 1000));
  for (;;) {
    const bool ask = !drain_.load();
    if (ask)
      *report.mutable_next() =
          MakeLeaseRequest(info_, WantJobs(o_.threads, mean_eval_s_, o_.max_batch));
    else
      report.clear_next();
    grpc::ClientContext ctx;
    rpc::PrepareCall(ctx, kReportDeadlineS, o_.token);
    v1::ReportResponse resp;
    SetLeaseCall(ask ? &ctx : nullptr);
    grpc::Status s = Stub()->Report(&ctx, report, &resp);
    SetLeaseCall(nullptr);
    if (ask && drain_.load() && s.error_code() == grpc::StatusCode::CANCELLED) continue;
    const ReportFate fate = ClassifyReport(s);
    if (fate == ReportFate::kLanded) {
      stats_.reported += resp.accepted();
      stats_.duplicates += resp.duplicates();
      if (ask) next->Swap(resp.mutable_lease());
      break;
    }
    if (fate == ReportFate::kDrop) {
      spdlog::error("report refused: {}", s.error_message());
      stats_.refused += n;
      break;
    }
    if (orphaned_.load()) {
      spdlog::warn("worker={} draining and the coordinator is gone: {} results not reported",
                   info_.worker_id(), n);
      break;
    }
    if (drain_.load() && Clock::now() > give_up) {
      spdlog::warn("draining: could not report {} results ({})", n, s.error_message());
      break;
    }
    spdlog::warn("report failed ({}); retrying", s.error_message());
    std::atomic<bool> never{false};
    SleepBackoff(backoff_, never);
  }
  backoff_.Reset();
}

void WorkerLoop::SetLeaseCall(grpc::ClientContext* ctx) {
  std::lock_guard<std::mutex> l(lease_mu_);
  lease_ctx_ = ctx;
}

int WorkerLoop::Run(WorkerStats* stats_out) {
  bool drained = false;
  if (!Connect(drained)) return 2;
  if (drained) return 0;
  info_ = MakeWorkerInfo(o_.worker_id, o_.threads, SimBuild(), registry_.Names());
  spdlog::info("worker={} ({} threads) pulling from {}", info_.worker_id(), o_.threads,
               copts_.target);
  std::thread heartbeat([this] { HeartbeatLoop(); });
  auto last_work = Clock::now();
  v1::LeaseResponse lease;
  bool in_hand = false;  // a batch came with the last report: evaluated even when draining
  while (in_hand || !drain_.load()) {
    if (o_.exit_when_idle_s > 0 &&
        std::chrono::duration<double>(Clock::now() - last_work).count() > o_.exit_when_idle_s)
      break;
    if (!in_hand) {
      lease.Clear();
      const Leased leased = Lease(lease);
      if (leased == Leased::kStop) break;
      if (leased != Leased::kJobs) continue;
    }
    in_hand = false;
    last_work = Clock::now();
    holding_ = true;
    if (!FillDescriptors(lease)) {
      holding_ = false;
      continue;  // the loop ends here if draining
    }
    Fetched fetched;
    if (!FetchRecordings(lease, fetched)) {
      // Draining while the coordinator is unreachable: a transient error must not become a
      // result (results depend only on the job), so the batch goes back by lease expiry.
      holding_ = false;
      break;
    }
    v1::LeaseResponse next;
    v1::ReportRequest report = Evaluate(lease, fetched);
    if (orphaned_.load()) {
      holding_ = false;
      break;
    }
    SendReport(std::move(report), &next);
    holding_ = false;
    if (next.jobs_size() > 0) {
      if (!TakeLease(next)) break;
      lease.Swap(&next);
      in_hand = true;
    }
  }
  stop_heartbeat_ = true;
  heartbeat.join();
  spdlog::info("worker={} exits: {} evaluated, {} accepted, {} duplicates, {} refused",
               info_.worker_id(), stats_.evaluated, stats_.reported, stats_.duplicates,
               stats_.refused);
  if (stats_out) *stats_out = stats_;
  return code_;
}

}  // namespace

std::string SimBuild() { return core::BuildId(); }

int RunWorker(const WorkerOptions& options, const objectives::ObjectiveRegistry& registry,
              std::atomic<bool>& drain, WorkerStats* stats_out) {
  WorkerLoop loop(options, registry, drain);
  return loop.Run(stats_out);
}

}  // namespace gaitforge::worker
