// gaitforge: the command-line client.
#include <cstdlib>
#include <iostream>
#include <thread>

#include "clients/cli/cli.h"
#include "services/core/flags.h"
#include "services/rpc/channel.h"

using namespace gaitforge;

namespace {

const char* kCommands =
    "commands:\n"
    "  local SPEC      run a study on this machine: a coordinator, N workers, SQLite under "
    "./runs/\n"
    "  submit SPEC     create a study on a coordinator (--coordinator); prints its id\n"
    "  watch ID        progress bar until the study ends (exit 0 if it completed)\n"
    "  list            every study\n"
    "  show ID         one study\n"
    "  hof ID          hall of fame (--generation G for an earlier one)\n"
    "  history ID      best, mean and diversity per generation (--json or --csv)\n"
    "  individuals ID  every member of --generation G (CSV, or --json)\n"
    "  plot ID         figures as SVG files (fitness per generation) under --out\n"
    "  report ID       caterpillar studies: fitness, gait diagrams, period sweep, travelling\n"
    "                  wave (paper 000 Figs. 8, 13, 14) and the best gait's markers, under --out\n"
    "  trajectory ID   markers of a hall-of-fame gait as a recording CSV (--output FILE.csv,\n"
    "                  --rank R, --generation G, --rate HZ, --cycles N)\n"
    "  diagnose SPEC   the gap finder: locate a sim-to-real mismatch, name the missing physics,\n"
    "                  fit it and show the held-out error fall (docs/diagnosis.md)\n"
    "  recording add FILE.csv   upload a recording (+ FILE.csv.json sidecar); prints its hash\n"
    "  recording list           the stored recordings\n"
    "  robots [NAME|FILE]       the built-in robots; one robot's parameters, genes and channels;\n"
    "                           a descriptor file checked (docs/robots.md)\n"
    "  resume ID       continue a cancelled or interrupted study\n"
    "  cancel ID       stop a study; its results stay\n"
    "\n"
    "Without --coordinator, commands work on the local database (--db), starting a private\n"
    "coordinator for as long as they run. Exit codes: 0 ok, 1 study ended not completed,\n"
    "2 bad input, 3 not found, 4 coordinator unavailable, 5 other error, 6 token missing\n"
    "or not allowed (docs/cli.md).\n";

}  // namespace

int main(int argc, char** argv) {
  cli::GlobalOptions g;
  if (const char* env = std::getenv("GAITFORGE_COORDINATOR")) g.coordinator = env;
  int workers = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  int threads = 1;
  int generation = -1;
  std::string out_dir = "runs/plots";
  std::string output;
  std::string sidecar;
  int rank = 0;
  int cycles = 3;
  double rate = 100;
  core::Flags flags("gaitforge COMMAND [ARGS] [flags]",
                    "Evolves gaits and calibrates simulations of soft robots on a gaitforge "
                    "coordinator and its workers.\n\n" + std::string(kCommands));
  flags.Add("coordinator", &g.coordinator,
            "coordinator address host:port (env GAITFORGE_COORDINATOR); empty: local database");
  flags.Add("db", &g.db, "local SQLite database used without --coordinator");
  flags.Add("timeout", &g.timeout_s, "deadline of each call, in seconds");
  flags.AddBool("json", &g.json, "machine-readable JSON output");
  flags.AddBool("csv", &g.csv, "CSV output (history, hof)");
  flags.Add("workers", &workers, "local/resume: worker processes to start (default: cores)");
  flags.Add("threads", &threads, "local/resume: evaluation threads per worker");
  flags.Add("generation", &generation, "hof/individuals: which generation");
  flags.Add("tls-ca", &g.tls_ca, "PEM CA: connect to --coordinator with TLS, trusting this CA");
  flags.Add("tls-cert", &g.tls_cert, "PEM client certificate (for servers that require one)");
  flags.Add("tls-key", &g.tls_key, "PEM key of --tls-cert");
  std::string token_file;
  flags.Add("token-file", &token_file, "file holding the client token (else env GAITFORGE_TOKEN)");
  flags.Add("out", &out_dir, "plot/report/local: directory for figures");
  flags.Add("output", &output, "trajectory: CSV file to write");
  flags.Add("sidecar", &sidecar, "recording add: the JSON sidecar (default FILE.csv.json)");
  flags.Add("rank", &rank, "trajectory: hall-of-fame rank (0 = best)");
  flags.Add("rate", &rate, "trajectory: marker sampling rate, Hz");
  flags.Add("cycles", &cycles, "trajectory: measured gait cycles");
  if (auto s = flags.Parse(argc, argv); !s.ok()) {
    std::cerr << "gaitforge: " << s.message() << "\n";
    return cli::kUsage;
  }
  const auto& pos = flags.positional();
  if (flags.help_requested() || pos.empty()) {
    std::cout << flags.Help();
    return pos.empty() && !flags.help_requested() ? cli::kUsage : cli::kOk;
  }
  if (workers < 1 || workers > 256 || threads < 1 || threads > 256) {
    std::cerr << "gaitforge: --workers and --threads must be in [1, 256]\n";
    return cli::kUsage;
  }
  if (g.timeout_s <= 0 || g.timeout_s > 86400) {
    std::cerr << "gaitforge: --timeout must be in (0, 86400] seconds\n";
    return cli::kUsage;
  }
  auto token = rpc::LoadToken(token_file, "GAITFORGE_TOKEN");
  if (!token.ok()) {
    std::cerr << "gaitforge: " << token.status().message() << "\n";
    return cli::kUsage;
  }
  g.token = *token;
  cli::SetCallToken(g.coordinator.empty() ? "" : g.token);
  const std::string cmd = pos[0];
  const std::vector<std::string> args(pos.begin() + 1, pos.end());
  if (cmd == "local") return cli::CmdLocal(g, args, workers, threads, out_dir);
  if (cmd == "submit") return cli::CmdSubmit(g, args);
  if (cmd == "watch") return cli::CmdWatch(g, args);
  if (cmd == "list") return cli::CmdList(g, args);
  if (cmd == "show") return cli::CmdShow(g, args);
  if (cmd == "hof") return cli::CmdHof(g, args, generation, generation >= 0);
  if (cmd == "history") return cli::CmdHistory(g, args);
  if (cmd == "individuals") {
    if (generation < 0) {
      std::cerr << "gaitforge: individuals needs --generation G\n";
      return cli::kUsage;
    }
    return cli::CmdIndividuals(g, args, generation);
  }
  if (cmd == "resume") return cli::CmdResume(g, args, workers, threads, out_dir);
  if (cmd == "cancel") return cli::CmdCancel(g, args);
  if (cmd == "plot") return cli::CmdPlot(g, args, out_dir);
  if (cmd == "diagnose") return cli::CmdDiagnose(g, args, workers, threads, out_dir);
  if (cmd == "robots") return cli::CmdRobots(g, args);
  if (cmd == "recording") return cli::CmdRecording(g, args, sidecar);
  if (cmd == "report") return cli::CmdReport(g, args, out_dir);
  if (cmd == "trajectory")
    return cli::CmdTrajectory(g, args, rank, generation, output, rate, cycles);
  std::cerr << "gaitforge: unknown command '" << cmd << "'\n" << kCommands;
  return cli::kUsage;
}
