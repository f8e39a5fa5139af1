// gaitforge-swarm: N emulated gaitforge-workers in one process against a real coordinator
// (issue 30). Each has its own gRPC connection and speaks the real worker's protocol
// (workers/protocol), but evaluates by waiting a drawn time and returns the real
// objective's fitness. Submits the studies, watches them to the end, prints JSON figures:
// dispatch efficiency, lease latency, generation turnaround, wire traffic, and the CPU of
// the swarm and of the coordinator (--coordinator-pid) apart. docs/scaling.md.
#include <spdlog/spdlog.h>

#include <future>
#include <iostream>
#include <random>
#include <thread>

#include "absl/strings/str_cat.h"
#include "bench/swarm/emulated_worker.h"
#include "bench/swarm/proc_stats.h"
#include "bench/swarm/report.h"
#include "bench/swarm/studies.h"
#include "services/core/build_info.h"
#include "services/core/flags.h"
#include "services/core/logging.h"
#include "services/rpc/channel.h"
#include "services/spec/spec_loader.h"
#include "services/rpc/process.h"

using namespace gaitforge;
using namespace gaitforge::swarm;

namespace {

struct Options {
  std::string coordinator = "127.0.0.1:50051", spec, eval = "constant:0.5", token_file;
  int workers = 16, studies = 1, max_batch = 256, seed = 1, loops = 2;
  int64_t coordinator_pid = 0;
  double kill_fraction = 0, kill_from_s = 2, kill_window_s = 5;
};

absl::Status ParseOptions(int argc, char** argv, Options& o, bool& help, std::string& usage) {
  core::Flags f("gaitforge-swarm --spec FILE [flags]",
                "N emulated workers (one connection each, the real worker's protocol, "
                "evaluations replaced by a drawn wait) run the studies; prints JSON figures.");
  f.Add("coordinator", &o.coordinator, "coordinator address, host:port");
  f.Add("spec", &o.spec, "study spec (YAML or JSON); its objective's fitness is computed for real");
  f.Add("studies", &o.studies, "studies submitted at once, seeds spec.seed + 0, 1, ...");
  f.Add("workers", &o.workers, "emulated workers (1..20000)");
  f.Add("eval", &o.eval, "evaluation time: constant:S or lognormal:MEAN:SIGMA (seconds)");
  f.Add("loops", &o.loops,
        "event-loop threads the workers are spread over (1..64; real workers run in "
        "parallel, one loop would serialise their steps at every generation barrier)");
  f.Add("max-batch", &o.max_batch, "most jobs per lease, as gaitforge-worker --max-batch");
  f.Add("coordinator-pid", &o.coordinator_pid, "measure this process's CPU and memory");
  f.Add("kill-fraction", &o.kill_fraction,
        "kill -9 this fraction of the workers (each restarts 1 s later with a new id)");
  f.Add("kill-from", &o.kill_from_s, "kills start this many seconds after the studies");
  f.Add("kill-window", &o.kill_window_s, "and are spread uniformly over this many seconds");
  f.Add("seed", &o.seed, "seed of the kill schedule");
  f.Add("token-file", &o.token_file, "worker+client (admin) token; else env GAITFORGE_TOKEN");
  auto s = f.Parse(argc, argv);
  help = f.help_requested();
  usage = f.Help();
  if (!s.ok() || help) return s;
  if (o.spec.empty()) return absl::InvalidArgumentError("--spec is required");
  if (o.workers < 1 || o.workers > 20000)
    return absl::InvalidArgumentError("--workers is out of range [1, 20000]");
  if (o.studies < 1 || o.studies > 1000)
    return absl::InvalidArgumentError("--studies is out of range [1, 1000]");
  if (o.loops < 1 || o.loops > 64)
    return absl::InvalidArgumentError("--loops is out of range [1, 64]");
  return absl::OkStatus();
}

// Kills round(fraction * N) distinct workers at uniform times in the window.
void ScheduleKills(const Options& o, std::vector<std::unique_ptr<EmulatedWorker>>& workers) {
  const int kills = static_cast<int>(o.kill_fraction * o.workers + 0.5);
  std::mt19937 rng(static_cast<uint32_t>(o.seed));
  std::vector<int> order(workers.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::shuffle(order.begin(), order.end(), rng);
  std::uniform_real_distribution<double> when(o.kill_from_s, o.kill_from_s + o.kill_window_s);
  for (int k = 0; k < kills && k < static_cast<int>(order.size()); ++k) {
    EmulatedWorker* w = workers[order[k]].get();
    w->loop().After(static_cast<int>(when(rng) * 1000), [w, k] {
      w->Kill(1000, absl::StrCat("swarm-", getpid(), "-reborn-", k));
    });
  }
}

}  // namespace

int main(int argc, char** argv) {
  rpc::DisableAbslDeadlockDetection();
  Options o;
  bool help = false;
  std::string usage;
  if (auto s = ParseOptions(argc, argv, o, help, usage); !s.ok()) {
    std::cerr << "gaitforge-swarm: " << s.message() << "\n";
    return 2;
  }
  if (help) {
    std::cout << usage;
    return 0;
  }
  // Logs to stderr: stdout carries only the JSON figures.
  if (auto s = core::SetupLogging("gaitforge-swarm", "warn", false); !s.ok()) return 2;
  auto loaded = spec::LoadSpecFile(o.spec);
  if (!loaded.ok()) {
    std::cerr << "gaitforge-swarm: " << loaded.status().message() << "\n";
    return 2;
  }
  if (!loaded->spec.objective().robot_descriptor().empty()) {
    // Emulated workers evaluate without fetching (no GetRobot): a built-in robot or an
    // analytic objective.
    std::cerr << "gaitforge-swarm: " << o.spec << ": field 'objective.robot' names a "
              << "descriptor file; the swarm runs built-in robots and analytic objectives only\n";
    return 2;
  }
  auto durations = Durations::Parse(o.eval);
  auto token = rpc::LoadToken(o.token_file, "GAITFORGE_TOKEN");
  if (!durations.ok() || !token.ok()) {
    std::cerr << "gaitforge-swarm: "
              << (durations.ok() ? token.status() : durations.status()).message() << "\n";
    return 2;
  }
  const int64_t nofile = RaiseFileLimit();
  const objectives::ObjectiveRegistry registry = objectives::DefaultRegistry();
  // Worker i runs on loop i % L, with that loop's figures (merged at the end).
  std::vector<std::unique_ptr<EventLoop>> loops;
  std::vector<SwarmStats> stats(o.loops);
  std::vector<std::unique_ptr<EmulatedWorker>> workers;
  for (int l = 0; l < o.loops; ++l) loops.push_back(std::make_unique<EventLoop>());
  for (int i = 0; i < o.workers; ++i) {
    const int l = i % o.loops;
    WorkerEnv env{o.coordinator, *token, core::BuildId(), o.max_batch, &registry,
                  &*durations, loops[l].get(), &stats[l]};
    workers.push_back(std::make_unique<EmulatedWorker>(env, absl::StrCat("swarm-", getpid(), "-", i)));
  }
  std::vector<std::thread> loop_threads;
  for (auto& loop : loops) loop_threads.emplace_back([&loop] { loop->Run(); });
  for (auto& w : workers) w->loop().Post([&w] { w->Start(); });
  std::this_thread::sleep_for(std::chrono::milliseconds(500 + o.workers));  // connect

  RunWindow win;
  win.start = Clock::now();
  win.self_cpu0 = SelfCpuSeconds();
  win.coord_cpu0 = o.coordinator_pid ? ProcessCpuSeconds(o.coordinator_pid) : 0;
  auto ids = SubmitStudies(o.coordinator, *token, loaded->spec, o.studies);
  if (!ids.ok()) {
    std::cerr << "gaitforge-swarm: " << ids.status().message() << "\n";
    _exit(1);
  }
  if (o.kill_fraction > 0) ScheduleKills(o, workers);
  WatchTraffic traffic;
  const std::vector<std::string> states = WatchToEnd(o.coordinator, *token, *ids, traffic);
  win.end = Clock::now();
  win.self_cpu1 = SelfCpuSeconds();
  if (o.coordinator_pid) {
    win.coord_cpu1 = ProcessCpuSeconds(o.coordinator_pid);
    win.coord_memory = ProcessMemory(o.coordinator_pid);
  }
  // The last generation's reports also asked for a next batch and wait for it (up to the
  // long poll's wait): let them come back, so that their results are counted.
  std::this_thread::sleep_for(std::chrono::milliseconds(worker::kLeaseWaitMs + 500));
  // Stop every worker on its loop, then the loops; the figures are read after that.
  std::vector<std::promise<void>> stopped(loops.size());
  for (size_t l = 0; l < loops.size(); ++l)
    loops[l]->Post([&, l] {
      for (size_t i = l; i < workers.size(); i += loops.size()) workers[i]->Stop();
      stopped[l].set_value();
    });
  for (auto& p : stopped) p.get_future().get();
  for (size_t l = 0; l < loops.size(); ++l) {
    loops[l]->Stop();
    loop_threads[l].join();
    if (l > 0) stats[0].Merge(stats[l]);
  }
  stats[0].Close();
  std::cout << ReportJson(o.workers, o.eval, nofile, *ids, states, win, stats[0], traffic)
            << std::endl;
  bool all_completed = true;
  for (const auto& s : states) all_completed &= s == "completed";
  // Callbacks of cancelled calls may still arrive: leave without tearing the workers down.
  std::cout.flush();
  _exit(all_completed ? 0 : 1);
}
