#pragma once
// The pull loop of gaitforge-worker: lease a batch, evaluate it on --threads threads,
// report, repeat; heartbeats from another thread. Keeps no state beyond the batch in hand.
#include <atomic>
#include <cstdint>
#include <string>

#include "workers/objectives/objective.h"

namespace gaitforge::worker {

struct WorkerOptions {
  std::string coordinator = "127.0.0.1:50051";
  int threads = 1;
  // Upper bound of jobs per lease; the worker asks for up to about 5 s of work per lease
  // (workers/protocol/wire.h, kBatchHeadroom x kTargetBatchSeconds).
  int max_batch = 256;
  std::string worker_id;  // empty: host-pid-random
  // Exit after this long without work (0: never).
  double exit_when_idle_s = 0;
  // Read host:port from this file (waiting until it exists, and again after the
  // coordinator has been unreachable), instead of `coordinator`.
  std::string coordinator_file;
  std::string tls_ca, tls_cert, tls_key;  // TLS (see rpc::ChannelOptions)
  std::string token;                      // bearer token (worker role)
};

struct WorkerStats {
  int64_t evaluated = 0;
  int64_t reported = 0;
  int64_t duplicates = 0;
  int64_t refused = 0;
};

// Runs until `drain` becomes true (then finishes and reports the batch in hand) or the
// idle limit passes. Returns 0 on a clean exit.
int RunWorker(const WorkerOptions& options, const objectives::ObjectiveRegistry& registry,
              std::atomic<bool>& drain, WorkerStats* stats = nullptr);

// Identity of this simulator build (version, compiler, physics library); see docs/protocol.md.
std::string SimBuild();

}  // namespace gaitforge::worker
