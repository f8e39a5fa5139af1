// gaitforge: the command-line client.
#include <cstdlib>
#include <iostream>
#include <thread>

#include "clients/cli/cli.h"
#include "clients/cli/command_help.h"
#include "services/core/build_info.h"
#include "services/core/flags.h"
#include "services/rpc/channel.h"

using namespace gaitforge;

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
                    "coordinator and its workers.\n\n" + cli::CommandList());
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
  flags.Add("output", &output,
            "trajectory/export: CSV file to write; diagnose plan: the plan's JSON (default: "
            "plan.json beside --report)");
  diagnosis::plan::Options plan;
  diagnosis::plan::AddFlags(flags, &plan, "diagnose plan");
  flags.Add("sidecar", &sidecar, "recording add: the JSON sidecar (default FILE.csv.json)");
  std::string robot_file;
  flags.Add("robot", &robot_file,
            "recording add: the descriptor of the robot the recording names when it is not "
            "built in (docs/robots.md)");
  flags.Add("rank", &rank, "trajectory/export: hall-of-fame rank (0 = best)");
  flags.Add("rate", &rate, "trajectory: marker sampling rate; export: command rate, Hz");
  flags.Add("cycles", &cycles, "trajectory: measured gait cycles; export: cycles written");
  cli::ValidateOptions validate;
  int64_t validate_seed = 0;
  flags.Add("members", &validate.members,
            "validate: members of the fresh ensemble (default: 4x the study's, at most 256)");
  flags.Add("ensemble-seed", &validate_seed,
            "validate: the fresh ensemble's seed (default: the study's ensemble seed + 1)");
  flags.Add("top", &validate.top, "validate: the first N hall-of-fame gaits (default: all)");
  flags.Add("gaits", &validate.gaits,
            "validate: a file of gaits to validate instead, one per line (genes separated by "
            "spaces or commas)");
  flags.Add("from-calibration", &validate.from_calibration,
            "validate: predict the gaits with this calibration study's model and open ranges "
            "instead of the study's own");
  std::string dashboard = "127.0.0.1:0";
  flags.Add("dashboard", &dashboard,
            "local/resume/diagnose/dashboard: serve the web dashboard at HOST:PORT (port 0: any "
            "free one; off: none)");
  bool version = false;
  flags.AddBool("version", &version, "print the build's identity (what workers report) and exit");
  if (auto s = flags.Parse(argc, argv); !s.ok()) {
    std::cerr << "gaitforge: " << s.message() << "\n";
    return cli::kUsage;
  }
  const auto& pos = flags.positional();
  if (version) {
    std::cout << core::BuildId() << "\n";
    return cli::kOk;
  }
  const cli::CommandHelp* command = pos.empty() ? nullptr : cli::FindCommand(pos[0]);
  if (flags.help_requested() && command) {
    std::cout << flags.Help("gaitforge " + command->name +
                                (command->args.empty() ? "" : " " + command->args) + " [flags]",
                            command->details + "\n\nexample:\n  " + command->example,
                            command->flags);
    return cli::kOk;
  }
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
  // Only the commands that run studies (and `dashboard`) serve the dashboard.
  if (dashboard != "off" &&
      (cmd == "local" || cmd == "resume" || cmd == "diagnose" || cmd == "dashboard"))
    g.dashboard = dashboard;
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
  if (cmd == "validate") {
    if (validate_seed < 0 || validate.members < 0 || validate.members > 256 || validate.top < 0) {
      std::cerr << "gaitforge: validate: --ensemble-seed >= 0, --members in [0, 256], --top >= 0\n";
      return cli::kUsage;
    }
    validate.seed = static_cast<uint64_t>(validate_seed);
    return cli::CmdValidate(g, args, workers, threads, validate);
  }
  if (cmd == "plot") return cli::CmdPlot(g, args, out_dir);
  if (cmd == "diagnose" && !args.empty() && args[0] == "plan") {
    plan.threads = workers;
    return cli::CmdDiagnosePlan(g, std::vector<std::string>(args.begin() + 1, args.end()), plan,
                                output);
  }
  if (cmd == "diagnose") return cli::CmdDiagnose(g, args, workers, threads, out_dir);
  if (cmd == "diagnosis") return cli::CmdDiagnosis(g, args, out_dir);
  if (cmd == "diagnoses") return cli::CmdDiagnoses(g, args);
  if (cmd == "robots") return cli::CmdRobots(g, args);
  if (cmd == "recording") return cli::CmdRecording(g, args, sidecar, robot_file);
  if (cmd == "report") return cli::CmdReport(g, args, out_dir);
  if (cmd == "export") return cli::CmdExport(g, args, rank, generation, output, rate, cycles);
  if (cmd == "trajectory")
    return cli::CmdTrajectory(g, args, rank, generation, output, rate, cycles);
  if (cmd == "health") return cli::CmdHealth(g, args);
  if (cmd == "dashboard") return cli::CmdDashboard(g, args);
  std::cerr << "gaitforge: unknown command '" << cmd << "'\n" << cli::CommandList();
  return cli::kUsage;
}
