#pragma once
// One emulated gaitforge-worker (--threads 1): its own channel to the coordinator, the same
// protocol code (workers/protocol: requests, batch sizing, retry classes, backoff,
// heartbeat pacing, the real objective's fitness) driven by gRPC's callback API on the
// swarm's event loop; "evaluating" is waiting a drawn time.
#include <grpcpp/grpcpp.h>

#include <memory>
#include <string>

#include "bench/swarm/durations.h"
#include "bench/swarm/event_loop.h"
#include "bench/swarm/swarm_stats.h"
#include "gaitforge/v1/worker.grpc.pb.h"
#include "workers/objectives/objective.h"
#include "workers/protocol/wire.h"

namespace gaitforge::swarm {

struct WorkerEnv {
  std::string target;
  std::string token;
  std::string sim_build;
  int max_batch = 256;
  const objectives::ObjectiveRegistry* registry = nullptr;
  const Durations* durations = nullptr;
  EventLoop* loop = nullptr;
  SwarmStats* stats = nullptr;
};

class EmulatedWorker {
 public:
  EmulatedWorker(const WorkerEnv& env, std::string worker_id);
  // Connects (a channel of its own) and starts pulling.
  void Start();
  // Like kill -9: in-flight calls are cancelled, the batch in hand is lost (its leases
  // expire), and the worker comes back after `restart_ms` as a new process (new id).
  void Kill(int restart_ms, std::string new_id);
  // Stops issuing calls (end of the run).
  void Stop();
  bool idle() const { return phase_ == Phase::kStopped; }
  // The event loop that runs this worker's steps (Kill and Stop must run there).
  EventLoop& loop() const { return *env_.loop; }

 private:
  enum class Phase { kLeasing, kEvaluating, kReporting, kBackoff, kStopped };
  struct Call;  // one RPC in flight

  void SendLease();
  void OnLease(const grpc::Status& s, v1::LeaseResponse& resp, Clock::time_point sent,
               Clock::time_point received);
  // A batch's jobs (from a Lease, or with a Report's answer): evaluated, then waited for.
  void TakeJobs(v1::LeaseResponse& resp, Clock::time_point sent, Clock::time_point received);
  void FinishBatch();
  void SendReport();
  void OnReport(const grpc::Status& s, v1::ReportResponse& resp, Clock::time_point sent);
  void HeartbeatTick(uint64_t incarnation, uint64_t batch);
  void Retry(void (EmulatedWorker::*step)());
  // Wraps a continuation so that it does nothing once the worker was killed or stopped.
  template <typename F>
  auto Guard(F f);

  WorkerEnv env_;
  v1::WorkerInfo info_;
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<v1::WorkerService::Stub> stub_;
  Phase phase_ = Phase::kStopped;
  uint64_t incarnation_ = 0;  // bumps on Kill/Stop; stale callbacks compare it
  uint64_t batch_seq_ = 0;
  worker::Backoff backoff_;
  double mean_eval_s_ = 0;
  int lease_ms_ = 10000;
  v1::LeaseResponse lease_;
  v1::ReportRequest report_;
  Clock::time_point batch_start_;
  std::shared_ptr<grpc::ClientContext> inflight_;  // cancelled by Kill
};

}  // namespace gaitforge::swarm
