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

}  // namespace

std::string SimBuild() { return core::BuildId(); }

int RunWorker(const WorkerOptions& options, const objectives::ObjectiveRegistry& registry,
              std::atomic<bool>& drain, WorkerStats* stats_out) {
  WorkerStats stats;
  rpc::ChannelOptions copts{options.coordinator, options.tls_ca, options.tls_cert, options.tls_key,
                            options.token};
  if (!options.coordinator_file.empty()) {
    // Wait for the coordinator to publish its address (Slurm: it may start after us).
    while ((copts.target = ReadAddressFile(options.coordinator_file)).empty()) {
      if (drain.load()) return 0;
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
    }
  }
  auto channel = rpc::MakeChannel(copts);
  if (!channel.ok()) {
    spdlog::error("{}", std::string(channel.status().message()));
    return 2;
  }
  std::shared_ptr<v1::WorkerService::Stub> stub = v1::WorkerService::NewStub(*channel);
  std::shared_ptr<v1::RecordingService::Stub> recordings_stub =
      v1::RecordingService::NewStub(*channel);
  std::mutex stub_mu;  // guards stub and recordings_stub (replaced when the coordinator moves)
  auto current_stub = [&] {
    std::lock_guard<std::mutex> l(stub_mu);
    return stub;
  };
  RecordingCache recordings([&](const std::string& hash)
                                -> absl::StatusOr<RecordingCache::Bytes> {
    std::shared_ptr<v1::RecordingService::Stub> rs;
    {
      std::lock_guard<std::mutex> l(stub_mu);
      rs = recordings_stub;
    }
    grpc::ClientContext ctx;
    rpc::PrepareCall(ctx, 60, options.token);
    v1::GetRecordingRequest req;
    req.set_hash(hash);
    v1::GetRecordingResponse resp;
    grpc::Status s = rs->GetRecording(&ctx, req, &resp);
    if (!s.ok())
      return absl::Status(static_cast<absl::StatusCode>(s.error_code()), s.error_message());
    return RecordingCache::Bytes{resp.recording().name(), resp.csv(), resp.sidecar()};
  });
  const v1::WorkerInfo info =
      MakeWorkerInfo(options.worker_id, options.threads, SimBuild(), registry.Names());
  spdlog::info("worker={} ({} threads) pulling from {}", info.worker_id(), options.threads,
               copts.target);

  // Heartbeats from their own thread, so a long evaluation never loses its lease. The same
  // thread cancels a pending long-poll Lease as soon as a drain is requested.
  std::atomic<int> lease_ms{10000};
  std::atomic<bool> holding{false};
  std::atomic<bool> stop_heartbeat{false};
  std::mutex lease_mu;
  grpc::ClientContext* lease_ctx = nullptr;  // guarded by lease_mu
  std::thread heartbeat([&] {
    auto last = Clock::now();
    while (!stop_heartbeat.load()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      if (drain.load()) {
        std::lock_guard<std::mutex> l(lease_mu);
        if (lease_ctx) lease_ctx->TryCancel();
      }
      if (Clock::now() - last < std::chrono::milliseconds(HeartbeatIntervalMs(lease_ms.load())))
        continue;
      last = Clock::now();
      if (!holding.load()) continue;
      grpc::ClientContext ctx;
      rpc::PrepareCall(ctx, kHeartbeatDeadlineS, options.token);
      const v1::HeartbeatRequest req = MakeHeartbeatRequest(info);
      v1::HeartbeatResponse resp;
      grpc::Status s = current_stub()->Heartbeat(&ctx, req, &resp);
      if (s.ok()) lease_ms = resp.lease_ms();
      else spdlog::debug("heartbeat failed: {}", s.error_message());
    }
  });

  BatchRunner runner(options.threads);
  Backoff backoff;
  double mean_eval_s = 0.0;  // running estimate of one evaluation's time
  auto last_work = Clock::now();
  int code = 0;
  while (!drain.load()) {
    if (options.exit_when_idle_s > 0 &&
        std::chrono::duration<double>(Clock::now() - last_work).count() > options.exit_when_idle_s)
      break;
    const v1::LeaseRequest lreq =
        MakeLeaseRequest(info, WantJobs(options.threads, mean_eval_s, options.max_batch));
    v1::LeaseResponse lease;
    {
      grpc::ClientContext ctx;
      rpc::PrepareCall(ctx, kLeaseDeadlineS, options.token);
      {
        std::lock_guard<std::mutex> l(lease_mu);
        lease_ctx = &ctx;
      }
      grpc::Status s = current_stub()->Lease(&ctx, lreq, &lease);
      {
        std::lock_guard<std::mutex> l(lease_mu);
        lease_ctx = nullptr;
      }
      if (drain.load() && s.error_code() == grpc::StatusCode::CANCELLED) break;
      if (!s.ok()) {
        if (!Retryable(s)) {
          spdlog::error("lease refused: {} ({})", s.error_message(),
                        static_cast<int>(s.error_code()));
          code = 3;
          break;
        }
        spdlog::warn("coordinator unreachable ({}); retrying", s.error_message());
        SleepBackoff(backoff, drain);
        if (!options.coordinator_file.empty()) {
          // A restarted coordinator may have moved (another node): follow its file.
          const std::string target = ReadAddressFile(options.coordinator_file);
          if (!target.empty() && target != copts.target) {
            copts.target = target;
            if (auto ch = rpc::MakeChannel(copts); ch.ok()) {
              std::lock_guard<std::mutex> l(stub_mu);
              stub = v1::WorkerService::NewStub(*ch);
              recordings_stub = v1::RecordingService::NewStub(*ch);
              spdlog::info("worker={} following the coordinator to {}", info.worker_id(), target);
            }
          }
        }
        continue;
      }
    }
    backoff.Reset();
    lease_ms = lease.lease_ms();
    if (lease.jobs_size() == 0) continue;
    last_work = Clock::now();
    holding = true;

    const int n = lease.jobs_size();
    // The recordings the batch names, fetched before evaluating so that a transient
    // network error delays the batch rather than changing its results.
    std::map<std::string, absl::StatusOr<std::shared_ptr<const recording::Recording>>> fetched;
    for (const auto& job : lease.jobs()) {
      // A robot the study carries may be the one its recordings name.
      std::shared_ptr<const robots::RobotDescriptor> robot;
      if (!job.objective().robot_descriptor().empty()) {
        auto resolved = robots::ResolveRobot(job.objective().robot(),
                                             job.objective().robot_descriptor());
        if (resolved.ok()) robot = *resolved;  // else the objective says why
      }
      for (const auto* list : {&job.objective().recordings()}) {
        for (const auto& hash : *list) {
          if (fetched.count(hash)) continue;
          for (;;) {
            auto r = recordings.Get(hash, robot.get());
            const grpc::StatusCode code = static_cast<grpc::StatusCode>(r.status().code());
            const bool transient = !r.ok() && code != grpc::StatusCode::RESOURCE_EXHAUSTED &&
                                   Retryable(grpc::Status(code, std::string(r.status().message())));
            if (!transient) {
              fetched.emplace(hash, std::move(r));
              break;
            }
            if (drain.load()) break;  // leave the batch unevaluated: its leases expire
            spdlog::warn("worker={} fetching recording {}: {}; retrying", info.worker_id(), hash,
                         std::string(r.status().message()));
            SleepBackoff(backoff, drain);
          }
        }
      }
    }
    bool all_fetched = true;
    for (const auto& job : lease.jobs())
      for (const auto& hash : job.objective().recordings()) all_fetched &= fetched.count(hash) > 0;
    if (!all_fetched) {
      // Draining while the coordinator is unreachable: a transient error must not become a
      // result (results depend only on the job), so the batch goes back by lease expiry.
      holding = false;
      break;
    }
    v1::ReportRequest report = StartReport(info, lease);
    const auto t0 = Clock::now();
    runner.Run(n, [&](int i) {
      const auto start = Clock::now();
      const objectives::EvalResult r = EvaluateJob(registry, lease.jobs(i), fetched);
      FillResult(report.mutable_results(i), r,
                 std::chrono::duration<double>(Clock::now() - start).count());
    });
    const double batch_s = std::chrono::duration<double>(Clock::now() - t0).count();
    mean_eval_s = UpdateMeanEval(mean_eval_s, batch_s, options.threads, n);
    stats.evaluated += n;

    // Report until it lands; a draining worker gives up after about 10 s.
    const auto report_deadline =
        Clock::now() + std::chrono::milliseconds(static_cast<int>(kDrainReportGiveUpS * 1000));
    for (;;) {
      grpc::ClientContext ctx;
      rpc::PrepareCall(ctx, kReportDeadlineS, options.token);
      v1::ReportResponse resp;
      grpc::Status s = current_stub()->Report(&ctx, report, &resp);
      const ReportFate fate = ClassifyReport(s);
      if (fate == ReportFate::kLanded) {
        stats.reported += resp.accepted();
        stats.duplicates += resp.duplicates();
        break;
      }
      if (fate == ReportFate::kDrop) {
        spdlog::error("report refused: {}", s.error_message());
        stats.refused += n;
        break;
      }
      if (drain.load() && Clock::now() > report_deadline) {
        spdlog::warn("draining: could not report {} results ({})", n, s.error_message());
        break;
      }
      spdlog::warn("report failed ({}); retrying", s.error_message());
      std::atomic<bool> never{false};
      SleepBackoff(backoff, never);
    }
    backoff.Reset();
    holding = false;
  }
  stop_heartbeat = true;
  heartbeat.join();
  spdlog::info("worker={} exits: {} evaluated, {} accepted, {} duplicates, {} refused",
               info.worker_id(), stats.evaluated, stats.reported, stats.duplicates,
               stats.refused);
  if (stats_out) *stats_out = stats;
  return code;
}

}  // namespace gaitforge::worker
