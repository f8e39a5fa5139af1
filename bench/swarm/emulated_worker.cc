#include "bench/swarm/emulated_worker.h"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "services/rpc/channel.h"
#include "workers/protocol/job_eval.h"

namespace gaitforge::swarm {

template <typename Req, typename Resp>
struct Rpc {
  grpc::ClientContext ctx;
  Req req;
  Resp resp;
  Clock::time_point t0 = Clock::now();
};

EmulatedWorker::EmulatedWorker(const WorkerEnv& env, std::string worker_id)
    : env_(env),
      info_(worker::MakeWorkerInfo(worker_id, 1, env.sim_build, env.registry->Names())) {}

template <typename F>
auto EmulatedWorker::Guard(F f) {
  return [this, inc = incarnation_, f = std::move(f)]() mutable {
    if (inc == incarnation_ && phase_ != Phase::kStopped) f();
  };
}

void EmulatedWorker::Start() {
  rpc::ChannelOptions o;
  o.target = env_.target;
  o.token = env_.token;
  o.own_connection = true;  // a worker is a process: one TCP connection each
  channel_ = *rpc::MakeChannel(o);
  stub_ = v1::WorkerService::NewStub(channel_);
  backoff_.Reset();
  mean_eval_s_ = 0;
  SendLease();
}

void EmulatedWorker::Stop() {
  ++incarnation_;
  phase_ = Phase::kStopped;
  if (inflight_) inflight_->TryCancel();
}

void EmulatedWorker::Kill(int restart_ms, std::string new_id) {
  Stop();
  ++env_.stats->kills;
  info_.set_worker_id(std::move(new_id));
  const uint64_t inc = incarnation_;
  env_.loop->After(restart_ms, [this, inc] {
    if (inc == incarnation_) Start();
  });
}

void EmulatedWorker::SendLease() {
  phase_ = Phase::kLeasing;
  auto call = std::make_shared<Rpc<v1::LeaseRequest, v1::LeaseResponse>>();
  call->req = worker::MakeLeaseRequest(
      info_, worker::WantJobs(1, mean_eval_s_, env_.max_batch));
  rpc::PrepareCall(call->ctx, worker::kLeaseDeadlineS, env_.token);
  inflight_ = std::shared_ptr<grpc::ClientContext>(call, &call->ctx);
  env_.stats->lease.request_bytes += static_cast<int64_t>(call->req.ByteSizeLong());
  stub_->async()->Lease(&call->ctx, &call->req, &call->resp, [this, call, inc = incarnation_](
                                                                  grpc::Status s) {
    const auto received = Clock::now();
    env_.loop->Post([this, call, s, received, inc] {
      if (inc == incarnation_ && phase_ != Phase::kStopped)
        OnLease(s, call->resp, call->t0, received);
    });
  });
}

void EmulatedWorker::OnLease(const grpc::Status& s, v1::LeaseResponse& resp,
                             Clock::time_point sent, Clock::time_point received) {
  SwarmStats& st = *env_.stats;
  ++st.lease.calls;
  inflight_.reset();
  if (!s.ok()) {
    ++st.lease.failed;
    if (!worker::Retryable(s)) {
      spdlog::error("worker={} lease refused: {}", info_.worker_id(), s.error_message());
      phase_ = Phase::kStopped;  // gaitforge-worker exits 3
      return;
    }
    Retry(&EmulatedWorker::SendLease);
    return;
  }
  st.lease.response_bytes += static_cast<int64_t>(resp.ByteSizeLong());
  backoff_.Reset();
  if (resp.jobs_size() == 0) {
    lease_ms_ = resp.lease_ms();
    ++st.empty_leases;
    SendLease();
    return;
  }
  TakeJobs(resp, sent, received);
}

void EmulatedWorker::TakeJobs(v1::LeaseResponse& resp, Clock::time_point sent,
                              Clock::time_point received) {
  SwarmStats& st = *env_.stats;
  if (auto e = worker::ExpandLease(resp); !e.ok()) {
    spdlog::error("worker={} {}", info_.worker_id(), std::string(e.message()));
    phase_ = Phase::kStopped;  // gaitforge-worker exits 3
    return;
  }
  lease_ms_ = resp.lease_ms();
  st.lease_ms.push_back(std::chrono::duration<double, std::milli>(received - sent).count());
  st.jobs_leased += resp.jobs_size();
  lease_.Swap(&resp);  // the call is done with it: no copy on the loop thread
  report_ = worker::StartReport(info_, lease_);
  // The objective's real result (a pure function of the job), at the drawn duration.
  double total = 0;
  for (int i = 0; i < lease_.jobs_size(); ++i) {
    const v1::Job& job = lease_.jobs(i);
    const auto gen = std::make_pair(job.key().study_id(), job.key().generation());
    st.first_lease.emplace(gen, received);
    if (!job.backup()) st.last_lease[gen] = received;
    const double d = env_.durations->Draw(job.key());
    worker::FillResult(report_.mutable_results(i),
                       worker::EvaluateJob(*env_.registry, job, {}), d);
    total += d;
  }
  phase_ = Phase::kEvaluating;
  // The evaluation starts when the jobs arrive; the fitness computed above is part of it.
  batch_start_ = received;
  const uint64_t batch = ++batch_seq_;
  const auto end = batch_start_ + std::chrono::microseconds(static_cast<int64_t>(total * 1e6));
  env_.loop->At(end, Guard([this] { FinishBatch(); }));
  env_.loop->After(worker::HeartbeatIntervalMs(lease_ms_),
                   Guard([this, batch] { HeartbeatTick(incarnation_, batch); }));
}

void EmulatedWorker::FinishBatch() {
  const auto now = Clock::now();
  env_.stats->busy.emplace_back(batch_start_, now);
  // A lease holds either pending jobs or backup copies, never both (services/queue).
  if (lease_.jobs(0).backup()) env_.stats->backup_busy.emplace_back(batch_start_, now);
  mean_eval_s_ = worker::UpdateMeanEval(
      mean_eval_s_, std::chrono::duration<double>(now - batch_start_).count(), 1,
      lease_.jobs_size());
  phase_ = Phase::kReporting;
  SendReport();
}

void EmulatedWorker::SendReport() {
  phase_ = Phase::kReporting;
  auto call = std::make_shared<Rpc<v1::ReportRequest, v1::ReportResponse>>();
  call->req.Swap(&report_);  // back in OnReport (a retry sends it again)
  // The next batch in the same call, as gaitforge-worker asks (it stops asking only when
  // draining, which emulated workers never do).
  *call->req.mutable_next() =
      worker::MakeLeaseRequest(info_, worker::WantJobs(1, mean_eval_s_, env_.max_batch));
  rpc::PrepareCall(call->ctx, worker::kReportDeadlineS, env_.token);
  inflight_ = std::shared_ptr<grpc::ClientContext>(call, &call->ctx);
  env_.stats->report.request_bytes += static_cast<int64_t>(call->req.ByteSizeLong());
  stub_->async()->Report(&call->ctx, &call->req, &call->resp,
                         [this, call, inc = incarnation_](grpc::Status s) {
                           env_.loop->Post([this, call, s, inc] {
                             if (inc != incarnation_ || phase_ == Phase::kStopped) return;
                             report_.Swap(&call->req);
                             OnReport(s, call->resp, call->t0);
                           });
                         });
}

void EmulatedWorker::OnReport(const grpc::Status& s, v1::ReportResponse& resp,
                              Clock::time_point sent) {
  SwarmStats& st = *env_.stats;
  ++st.report.calls;
  inflight_.reset();
  switch (worker::ClassifyReport(s)) {
    case worker::ReportFate::kLanded: {
      st.report.response_bytes += static_cast<int64_t>(resp.ByteSizeLong());
      st.results_accepted += resp.accepted();
      st.duplicates += resp.duplicates();
      // Stamped when sent: the answer waits for the next batch (SwarmStats::Close keeps a
      // generation's last report at or before the next one's first lease).
      for (const auto& r : report_.results()) {
        const auto gen = std::make_pair(r.key().study_id(), r.key().generation());
        auto [first, new_first] = st.first_report.emplace(gen, sent);
        if (!new_first) first->second = std::min(first->second, sent);
        auto [last, new_last] = st.last_report.emplace(gen, sent);
        if (!new_last) last->second = std::max(last->second, sent);
      }
      break;
    }
    case worker::ReportFate::kDrop:
      ++st.report.failed;
      st.refused += report_.results_size();
      spdlog::error("worker={} report refused: {}", info_.worker_id(), s.error_message());
      break;
    case worker::ReportFate::kRetry:
      ++st.report.failed;
      Retry(&EmulatedWorker::SendReport);
      return;
  }
  backoff_.Reset();
  if (resp.lease().jobs_size() > 0) return TakeJobs(*resp.mutable_lease(), sent, Clock::now());
  SendLease();
}

void EmulatedWorker::HeartbeatTick(uint64_t incarnation, uint64_t batch) {
  if (batch != batch_seq_ || (phase_ != Phase::kEvaluating && phase_ != Phase::kReporting))
    return;  // the batch is reported: heartbeats stop until the next one
  auto call = std::make_shared<Rpc<v1::HeartbeatRequest, v1::HeartbeatResponse>>();
  call->req = worker::MakeHeartbeatRequest(info_);
  rpc::PrepareCall(call->ctx, worker::kHeartbeatDeadlineS, env_.token);
  env_.stats->heartbeat.request_bytes += static_cast<int64_t>(call->req.ByteSizeLong());
  stub_->async()->Heartbeat(&call->ctx, &call->req, &call->resp,
                            [this, call, incarnation](grpc::Status s) {
                              env_.loop->Post([this, call, s, incarnation] {
                                SwarmStats& st = *env_.stats;
                                ++st.heartbeat.calls;
                                if (!s.ok()) ++st.heartbeat.failed;
                                else st.heartbeat.response_bytes += call->resp.ByteSizeLong();
                                if (s.ok() && incarnation == incarnation_)
                                  lease_ms_ = call->resp.lease_ms();
                              });
                            });
  env_.loop->After(worker::HeartbeatIntervalMs(lease_ms_),
                   Guard([this, incarnation, batch] { HeartbeatTick(incarnation, batch); }));
}

void EmulatedWorker::Retry(void (EmulatedWorker::*step)()) {
  phase_ = phase_ == Phase::kReporting ? Phase::kReporting : Phase::kBackoff;
  env_.loop->After(backoff_.NextDelayMs(), Guard([this, step] { (this->*step)(); }));
}

}  // namespace gaitforge::swarm
