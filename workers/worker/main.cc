// gaitforge-worker: a stateless worker that pulls evaluation jobs from a coordinator.
#include <signal.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <iostream>
#include <thread>

#include "services/core/flags.h"
#include "services/core/logging.h"
#include "workers/objectives/objective.h"
#include "services/rpc/channel.h"
#include "workers/sim/ode_runtime.h"
#include "workers/worker/registry.h"
#include "workers/worker/worker_loop.h"
#include "services/rpc/process.h"

using namespace gaitforge;

int main(int argc, char** argv) {
  rpc::DisableAbslDeadlockDetection();
  worker::WorkerOptions o;
  std::string log_level = "info";
  o.threads = 1;
  core::Flags flags("gaitforge-worker [flags]",
                    "Pulls batches of evaluation jobs from a gaitforge coordinator, evaluates "
                    "them on --threads threads and reports the results. Keeps no state: kill it "
                    "at any time. SIGTERM or SIGINT drains: the batch in hand is finished and "
                    "reported, then the worker exits 0.");
  flags.Add("coordinator", &o.coordinator, "coordinator address, host:port");
  flags.Add("threads", &o.threads, "evaluations run at once (1..256)");
  flags.Add("max-batch", &o.max_batch, "most jobs per lease (the worker aims at ~2 s of work)");
  flags.Add("worker-id", &o.worker_id, "identity shown in results (default host-pid-random)");
  flags.Add("exit-when-idle", &o.exit_when_idle_s, "exit after this many seconds without work (0: never)");
  flags.Add("coordinator-file", &o.coordinator_file,
            "read host:port from this file (the coordinator's --address-file), waiting for it");
  flags.Add("tls-ca", &o.tls_ca, "PEM CA: connect with TLS and trust this CA");
  flags.Add("tls-cert", &o.tls_cert, "PEM client certificate (for --tls-client-ca servers)");
  flags.Add("tls-key", &o.tls_key, "PEM key of --tls-cert");
  std::string token_file;
  flags.Add("token-file", &token_file,
            "file holding the worker token (else env GAITFORGE_WORKER_TOKEN)");
  std::string log_format = "text";
  flags.Add("log-format", &log_format, "text or json");
  flags.Add("log-level", &log_level, "trace, debug, info, warn, error or off");
  if (auto s = flags.Parse(argc, argv); !s.ok()) {
    std::cerr << "gaitforge-worker: " << s.message() << "\n";
    return 2;
  }
  if (flags.help_requested()) {
    std::cout << flags.Help();
    return 0;
  }
  if (o.threads < 1 || o.threads > 256) {
    std::cerr << "gaitforge-worker: --threads = " << o.threads << " is out of range [1, 256]\n";
    return 2;
  }
  if (o.max_batch < 1 || o.max_batch > 1024) {
    std::cerr << "gaitforge-worker: --max-batch = " << o.max_batch << " is out of range [1, 1024]\n";
    return 2;
  }
  auto token = rpc::LoadToken(token_file, "GAITFORGE_WORKER_TOKEN");
  if (!token.ok()) {
    std::cerr << "gaitforge-worker: " << token.status().message() << "\n";
    return 2;
  }
  o.token = *token;
  if (log_format != "text" && log_format != "json") {
    std::cerr << "gaitforge-worker: --log-format: expected text or json\n";
    return 2;
  }
  if (auto s = core::SetupLogging("worker", log_level, log_format == "json"); !s.ok()) {
    std::cerr << "gaitforge-worker: " << s.message() << "\n";
    return 2;
  }
  sim::InitProcess();  // ODE, once per process, before any thread starts

  sigset_t sigs;
  sigemptyset(&sigs);
  sigaddset(&sigs, SIGINT);
  sigaddset(&sigs, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &sigs, nullptr);
  std::atomic<bool> drain{false};
  std::thread signals([&] {
    int sig = 0;
    sigwait(&sigs, &sig);
    spdlog::info("signal {}: draining", sig);
    drain = true;
  });
  signals.detach();

  auto registry = worker::WorkerRegistry();
  if (!registry.ok()) {
    std::cerr << "gaitforge-worker: " << registry.status().message() << "\n";
    return 2;
  }
  return worker::RunWorker(o, *registry, drain);
}
