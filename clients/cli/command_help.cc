#include "clients/cli/command_help.h"

#include "absl/strings/str_cat.h"

namespace gaitforge::cli {
namespace {

// Flags of every command that talks to a coordinator (named or embedded).
std::vector<std::string> Connection(std::vector<std::string> more) {
  std::vector<std::string> out = {"coordinator", "db",       "timeout",   "tls-ca",
                                  "tls-cert",    "tls-key",  "token-file"};
  out.insert(out.end(), more.begin(), more.end());
  return out;
}

std::vector<CommandHelp> Build() {
  return {
      {"local", "SPEC",
       "run a study on this machine: a coordinator, N workers, SQLite under ./runs/",
       "Validates the spec, starts a coordinator on --db and --workers worker processes, runs\n"
       "the study to its end with a progress bar, then draws its figures under --out. The\n"
       "coordinator serves the web dashboard (--dashboard; docs/dashboard.md): its URL is\n"
       "printed as the study starts.\n"
       "Ctrl-C stops everything; 'gaitforge resume ID' continues the study.",
       {"db", "timeout", "workers", "threads", "out", "dashboard", "json"},
       "gaitforge local examples/analytic-ga.yaml --workers 2"},
      {"submit", "SPEC", "create a study on a coordinator (--coordinator); prints its id",
       "Validates the spec, uploads the recordings it names by file and creates the study on\n"
       "--coordinator, whose workers run it.",
       Connection({"json"}),
       "gaitforge --coordinator head:50051 --tls-ca ca.crt submit examples/analytic-cmaes.yaml"},
      {"watch", "ID", "progress bar until the study ends (exit 0 if it completed)",
       "Shows the study's progress until it ends. Exit 0 if it completed, 1 if it failed or\n"
       "was cancelled.",
       Connection({"json"}), "gaitforge watch analytic-ga-3f09a1"},
      {"list", "", "every study", "Every study: STUDY STATE OBJECTIVE GEN BEST EVALS.",
       Connection({"json"}), "gaitforge list --db runs/gaitforge.db"},
      {"show", "ID", "one study", "One study: its spec's essentials, state, progress and error.",
       Connection({"json"}), "gaitforge show analytic-ga-3f09a1"},
      {"hof", "ID", "hall of fame (--generation G for an earlier one)",
       "The hall of fame after the latest generation, or after --generation G.",
       Connection({"generation", "json", "csv"}),
       "gaitforge hof analytic-ga-3f09a1 --generation 10"},
      {"history", "ID", "best, mean and diversity per generation (--json or --csv)",
       "Per generation: best, mean, standard deviation, diversity, evaluations and invalid\n"
       "evaluations.",
       Connection({"json", "csv"}), "gaitforge history analytic-ga-3f09a1 --csv > history.csv"},
      {"individuals", "ID --generation G", "every member of --generation G (CSV, or --json)",
       "Every member of generation G as CSV: member, valid, fitness, carried, worker,\n"
       "eval_seconds, reason, genes.",
       Connection({"generation", "json"}),
       "gaitforge individuals analytic-ga-3f09a1 --generation 0"},
      {"plot", "ID", "figures as SVG files (fitness per generation) under --out",
       "Writes OUT/ID-history.json and OUT/ID-fitness.svg and prints the SVG's path.",
       Connection({"out"}), "gaitforge plot analytic-ga-3f09a1 --out figures"},
      {"report", "ID",
       "a study's figures under --out: the fitness curve, then what its objective\n"
       "                  and robot offer (calibration report, paper_gait figures)",
       "The fitness figure, then: for an objective that calibrates a robot the calibration\n"
       "report; for a gait study whose robot's descriptor lists `figures: [paper_gait]` its\n"
       "gait diagrams, period sweep, travelling waves and the best gait's markers\n"
       "(docs/cli.md). Prints every file written.",
       Connection({"out"}), "gaitforge report paper-ga-1c2d3e --out figures"},
      {"trajectory", "ID --output FILE.csv",
       "markers of a hall-of-fame gait as a recording CSV (--output FILE.csv,\n"
       "                  --rank R, --generation G, --rate HZ, --cycles N)",
       "Simulates the hall-of-fame gait --rank R of the latest generation (or --generation G)\n"
       "and writes its markers m1..m6 in the recording CSV format with a JSON sidecar.",
       Connection({"output", "rank", "generation", "rate", "cycles"}),
       "gaitforge trajectory paper-ga-1c2d3e --rank 0 --rate 100 --output best.csv"},
      {"export", "ID --output FILE.csv",
       "a hall-of-fame gait as the command timeline a robot's controller plays\n"
       "                  (--output FILE.csv, --rank R, --generation G, --rate HZ, --cycles N)",
       "Writes the controller commands of hall-of-fame gait --rank R (latest generation, or\n"
       "--generation G) at --rate HZ over --cycles N whole cycles: columns t, then one per\n"
       "actuator (on/off valves 1/0, servos their set-point in rad). --json adds each valve's\n"
       "ON windows in one cycle, or each servo's fastest set-point change against its speed\n"
       "limit (a warning on stderr when it exceeds it).",
       Connection({"output", "rank", "generation", "rate", "cycles"}),
       "gaitforge export paper-ga-1c2d3e --rank 0 --rate 200 --cycles 5 --output gait.csv"},
      {"validate", "ID",
       "a robust study's gaits over a fresh ensemble its selection never saw\n"
       "                  (--members M, --ensemble-seed S, --top N or --gaits FILE)",
       "Evaluates the hall of fame of robust study ID (its first --top N gaits, or the gaits\n"
       "of --gaits FILE, one per line) again, each over a fresh ensemble: the study's own\n"
       "objective and ranges, --members M members (default 4x the study's) drawn from\n"
       "--ensemble-seed S (default the study's ensemble seed + 1). The study ranked every gait\n"
       "on the same few members, so the mean of the gaits it kept is optimistic; the fresh\n"
       "mean is not. Runs as a study of its own (a sweep, one level per gait; local workers,\n"
       "or --coordinator's) and prints RANK NOW FITNESS PREDICTED VALIDATED [MIN, MAX] SD per\n"
       "gait, NOW its rank by the validated fitness (--json: each gait's genes, validated\n"
       "rank and validated mean, sd, min, max).\n\n"
       "--from-calibration CAL predicts them with calibration CAL's model instead: its fitted\n"
       "values and the ranges it leaves open replace the study's (as from_calibration makes\n"
       "them for a new study). After recording the best gaits and calibrating again on all\n"
       "recordings, this ranks the first study's gaits by the better model, with no second\n"
       "evolution: NOW is the order to try them on the robot in.",
       Connection({"members", "ensemble-seed", "top", "gaits", "from-calibration", "workers",
                   "threads", "json"}),
       "gaitforge validate robust-walk-1c2d3e --members 24 --top 5"},
      {"diagnose", "SPEC",
       "the gap finder: locate a sim-to-real mismatch, name the missing physics,\n"
       "                  fit it and show the held-out error fall (docs/diagnosis.md)",
       "Uploads the spec's recordings and asks the coordinator to run the diagnosis as a\n"
       "stored job (it calibrates the baseline, locates the mismatch, screens and refits the\n"
       "candidate effects, and decides found / none / ambiguous); waits for it, copies its\n"
       "report and figures into --out/NAME-diagnosis and prints it. The same spec again\n"
       "returns the stored diagnosis, or takes an interrupted one up where it stopped.\n\n"
       "gaitforge diagnose plan SPEC --report DIR/diagnosis.json: the recordings that would\n"
       "decide between the diagnosis's leading explanations. Simulates candidate gaits (the\n"
       "recorded ones longer and at other periods, random ones from the gene space) under\n"
       "the baseline and each fitted explanation, and proposes the --propose gaits whose\n"
       "channels part the most pairs by at least --decisive times the model's residual; the\n"
       "JSON (genotypes, cycles, durations, separations) goes to --output or plan.json beside\n"
       "the report. --workers: simulations at once.",
       Connection({"workers", "threads", "out", "dashboard", "json", "report", "propose",
                   "random", "rivals", "seed", "decisive", "output"}),
       "gaitforge diagnose examples/diagnosis-hose.yaml --workers 2\n  gaitforge diagnose plan "
       "examples/diagnosis-hose.yaml --report runs/plots/hose-diagnosis/diagnosis.json"},
      {"diagnoses", "",
       "the stored diagnoses: id, state, verdict, progress (docs/diagnosis.md)",
       "Lists every diagnosis in the database, oldest first; --json gives\n"
       "gaitforge.v1.ListDiagnosesResponse.",
       Connection({"json"}), "gaitforge diagnoses --json"},
      {"diagnosis", "ID",
       "a stored diagnosis: waits for it, copies its report and figures, prints it",
       "Waits while the diagnosis runs (progress on stderr), then copies its report and\n"
       "figures into --out/NAME-diagnosis and prints the report in words (--json: the report\n"
       "itself, docs/effects.md). Exit 1 when it failed, was cancelled or is interrupted.",
       Connection({"out", "json"}), "gaitforge diagnosis hose-4f2a9c --out figures"},
      {"recording", "add FILE.csv | list",
       "recording add FILE.csv: upload a recording (+ FILE.csv.json); prints its hash;\n"
       "                  recording list: the stored recordings",
       "add: uploads FILE.csv and its sidecar (FILE.csv.json, or --sidecar F) and prints its\n"
       "content hash; a recording of a robot that is not built in needs --robot ROBOT.yaml\n"
       "(its sensors give the channels it may hold). list: every stored recording.",
       Connection({"sidecar", "robot", "json"}), "gaitforge recording add walk.csv"},
      {"robots", "[NAME | FILE]",
       "the built-in robots; one robot's parameters, genes and channels; a\n"
       "                  descriptor file checked (docs/robots.md)",
       "Without an argument: the built-in robots. With a built-in robot's name: its\n"
       "parameters (value, range, whether a calibration may set it), scales, relations,\n"
       "genes and recording channels. With a path: checks that descriptor file (exit 2 with\n"
       "FILE:LINE:COLUMN on a mistake). Needs no coordinator.",
       {"json"}, "gaitforge robots tests/fixtures/robots/twobox/robot.yaml"},
      {"resume", "ID", "continue a cancelled or interrupted study",
       "Continues a cancelled, failed or interrupted study: with --coordinator there, else\n"
       "like 'local', with local workers.",
       Connection({"workers", "threads", "out", "dashboard", "json"}),
       "gaitforge resume analytic-ga-3f09a1"},
      {"dashboard", "", "the web dashboard of the local database, until Ctrl-C",
       "Prints the URL of a read-only web dashboard of --db (studies, live fitness curves,\n"
       "hall of fame with gait diagrams, history; diagnoses with their verdict, figures and\n"
       "candidates; docs/dashboard.md) and serves it until Ctrl-C. If a running\n"
       "'gaitforge local' holds the database, prints that one's URL.",
       {"db", "dashboard"}, "gaitforge dashboard --dashboard 127.0.0.1:8080"},
      {"cancel", "ID", "stop a study; its results stay", "Stops a study; its results stay.",
       Connection({"json"}), "gaitforge cancel analytic-ga-3f09a1"},
      {"health", "", "whether --coordinator serves (grpc.health.v1; no token needed)",
       "Asks --coordinator (or GAITFORGE_COORDINATOR) whether it serves: prints SERVING and\n"
       "exits 0, else says why and exits 4.",
       {"coordinator", "timeout", "tls-ca", "tls-cert", "tls-key"},
       "gaitforge --coordinator 127.0.0.1:50051 health"},
  };
}

}  // namespace

const std::vector<CommandHelp>& Commands() {
  static const std::vector<CommandHelp> commands = Build();
  return commands;
}

const CommandHelp* FindCommand(const std::string& name) {
  for (const auto& c : Commands())
    if (c.name == name) return &c;
  return nullptr;
}

std::string CommandList() {
  std::string out = "commands:\n";
  for (const auto& c : Commands()) {
    std::string head = absl::StrCat("  ", c.name, c.args.empty() ? "" : " ", c.args);
    // Long argument lists get a line of their own.
    if (head.size() < 18) head.resize(18, ' ');
    else head += "\n" + std::string(18, ' ');
    absl::StrAppend(&out, head, c.summary, "\n");
  }
  absl::StrAppend(
      &out,
      "\nWithout --coordinator, commands work on the local database (--db), starting a private\n"
      "coordinator for as long as they run. 'gaitforge COMMAND --help' describes one command.\n"
      "Exit codes: 0 ok, 1 study ended not completed, 2 bad input, 3 not found, 4 coordinator\n"
      "unavailable, 5 other error, 6 token missing or not allowed (docs/cli.md).\n");
  return out;
}

}  // namespace gaitforge::cli
