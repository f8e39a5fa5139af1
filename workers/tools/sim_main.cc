// gaitforge-sim: one-shot simulations of a robot with the workers' own model build.
//   trajectory    the robot's channels over one gait as a recording CSV (+ JSON sidecar)
//   period-sweep  distance per cycle as a gait's period is scaled (paper 000, Fig. 13)
//   wave          the travelling-wave baseline over periods (paper 000, Fig. 14)
//   calibration-eval  errors of the model (with --set overrides) against recordings, and
//                 the simulated markers of each recording's gait, for calibration reports
//   plan          the gaits whose recordings would separate a diagnosis's explanations
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <thread>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "robots/count_override.h"
#include "robots/registry.h"
#include "services/core/file_text.h"
#include "services/core/flags.h"
#include "services/recording/recording.h"
#include "workers/sim/ode_runtime.h"
#include "workers/tools/generic_sim.h"
#include "workers/tools/sim_learn.h"
#include "workers/tools/sim_plan.h"
#include "workers/tools/sim_tool.h"
#include "workers/tools/sim_track.h"

using namespace gaitforge;

namespace {

// The whole file at `path` ("" when it cannot be read).
std::string ReadWhole(const std::string& path) { return core::ReadWholeFile(path).value_or(""); }

// The descriptor a --robot names: a file's text, or a built-in robot's.
absl::StatusOr<std::pair<std::string, std::string>> RobotText(const std::string& arg) {
  if (std::filesystem::is_regular_file(arg)) return std::make_pair(arg, ReadWhole(arg));
  if (robots::FindRobot(arg) == nullptr)
    return absl::NotFoundError(absl::StrCat("--robot ", arg,
                                            ": neither a descriptor file nor a built-in robot"));
  return std::make_pair(std::string(), std::string(robots::BuiltinText(arg)));
}

// The robot of a run without --robot: calibration-eval, learn-parameters and plan take the one
// the first recording's sidecar names (a built-in robot); every other command needs --robot.
absl::StatusOr<std::string> DefaultRobot(const std::string& cmd, const std::string& recordings) {
  const std::string first = recordings.substr(0, recordings.find(','));
  if ((cmd != "calibration-eval" && cmd != "learn-parameters" && cmd != "plan") || first.empty())
    return absl::InvalidArgumentError(
        "--robot is required: a built-in robot's name (gaitforge robots list) or a descriptor "
        "file (docs/robots.md)");
  if (!std::filesystem::is_regular_file(first + ".json"))
    return absl::NotFoundError(absl::StrCat("cannot read ", first, ".json (the sidecar ",
                                            "that names the robot; or give --robot)"));
  auto robot = recording::SidecarRobot(ReadWhole(first + ".json"), first + ".json");
  if (!robot.ok())
    return absl::InvalidArgumentError(
        absl::StrCat(robot.status().message(), " (a robot that is only files: give --robot)"));
  return *robot;
}

struct Args {
  std::string cmd, robot, genes, out, set, recordings, options, params, out_dir, engine, inputs;
  std::string scales, periods, learned;
  std::vector<std::pair<std::string, int>> counts;  // --count: another resolution of the robot
  simtool::TrackArgs track;
  simtool::LearnArgs learn;
  simtool::PlanArgs plan;
  bool open_loop = false;
  double rate = 100;
  int cycles = 10, settle = 2, threads = 1;
};

int Fail(const absl::Status& s, int code) {
  std::cerr << "gaitforge-sim: " << s.message() << "\n";
  return code;
}

// period-sweep and wave: JSON of the sweep; an exit code.
int RunSweep(const Args& a, const simtool::GenericRun& run) {
  generic::ParamValues values(*run.robot);
  for (const auto& [name, value] : run.overrides)
    if (auto s = values.Set(name, value); !s.ok()) return Fail(absl::InvalidArgumentError(absl::StrCat("--set ", s.message())), 2);
  generic::GaitOptions o;
  o.measured_cycles = a.cycles;
  o.settle_cycles = a.settle;
  absl::StatusOr<std::vector<simtool::SweepPoint>> points;
  if (a.cmd == "wave") {
    auto periods = simtool::ParseRange(a.periods, false);
    if (!periods.ok()) return Fail(periods.status(), 2);
    points = simtool::WaveSweep(*run.robot, values, *periods, o, a.threads);
  } else {
    auto genes = simtool::ParseGenes(a.genes, run.robot->controller.genes.size());
    if (!genes.ok()) return Fail(genes.status(), 2);
    auto scales = simtool::ParseRange(a.scales, true);
    if (!scales.ok()) return Fail(scales.status(), 2);
    points = simtool::PeriodSweep(*run.robot, values, *genes, *scales, o, a.threads);
  }
  if (!points.ok()) return Fail(points.status(), 2);
  std::cout << simtool::SweepJson(*points) << "\n";
  return 0;
}

// Every command, on the robot --robot names (or the recordings' sidecar); an exit code.
int Run(const Args& a) {
  auto text = RobotText(a.robot);
  if (!text.ok()) return Fail(text.status(), 2);
  for (const auto& [name, value] : a.counts) {  // another resolution of the same robot
    auto finer = robots::WithCount(text->second, name, value, a.robot);
    if (!finer.ok()) return Fail(absl::InvalidArgumentError(absl::StrCat("--count ", finer.status().message())), 2);
    text->second = *finer;
    text->first = absl::StrCat(text->first.empty() ? a.robot : text->first, " (", name, " = ", value, ")");
  }
  auto robot = robots::ResolveRobot("", text->second);
  if (!robot.ok()) return Fail(robot.status(), 2);
  if ((*robot)->model != "generic")
    return Fail(absl::InvalidArgumentError(absl::StrCat("--robot ", a.robot, " has model ",
                                                        (*robot)->model,
                                                        "; gaitforge-sim builds model: generic")),
                2);
  simtool::GenericRun run;
  run.robot = robot->get();
  run.robot_path = text->first;
  run.robot_text = text->second;
  run.rate_hz = a.rate;
  run.cycles = a.cycles;
  run.settle_cycles = a.settle;
  run.engine = a.engine;
  const double h = run.robot->Value("simulation.timestep_s");
  const double steps = 1.0 / (a.rate * h);
  if ((a.cmd == "trajectory" || a.cmd == "calibration-eval") &&
      (!(a.rate > 0) || std::abs(steps - std::round(steps)) > 1e-9 || std::round(steps) < 1))
    return Fail(absl::InvalidArgumentError(absl::StrCat(
                    "--rate ", a.rate, " Hz is not a whole number of ", h,
                    " s steps; use 1 / (k h) Hz (at 1 ms: 100, 200, 250, 500)")), 2);
  auto overrides = simtool::ParseOverrides(a.set);
  if (!overrides.ok()) return Fail(overrides.status(), 2);
  run.overrides = *overrides;
  run.learned = a.learned;
  sim::InitProcess();
  if (a.cmd == "period-sweep" || a.cmd == "wave") return RunSweep(a, run);
  if (a.cmd == "learn-parameters") {
    simtool::LearnArgs l = a.learn;
    l.recordings = a.recordings;
    l.threads = a.threads;
    l.out = a.out;
    auto json = simtool::GenericLearn(run, l);
    if (!json.ok()) return Fail(json.status(), 2);
    std::cout << *json << "\n";
    return 0;
  }
  if (a.cmd == "track") {
    simtool::TrackArgs t = a.track;
    t.out = a.out;
    t.feedback = !a.open_loop;
    auto json = simtool::GenericTrack(run, t);
    if (!json.ok()) return Fail(json.status(), json.status().code() == absl::StatusCode::kAborted ? 1 : 2);
    std::cout << *json << "\n";
    return 0;
  }
  if (a.cmd == "plan") {
    simtool::PlanArgs p = a.plan;
    p.recordings = a.recordings;
    p.options.threads = a.threads;
    auto json = simtool::GenericPlan(run, p);
    if (!json.ok()) return Fail(json.status(), 2);
    std::cout << *json << "\n";
    return 0;
  }
  if (a.cmd == "trajectory" && !a.inputs.empty()) {
    if (a.out.empty()) return Fail(absl::InvalidArgumentError("trajectory needs --out FILE.csv"), 2);
    if (auto s = simtool::GenericPlayback(run, a.inputs, a.out); !s.ok())
      return Fail(s, s.code() == absl::StatusCode::kAborted ? 1 : 2);
    std::cout << a.out << "\n";
    return 0;
  }
  if (a.cmd == "trajectory") {
    auto genes = simtool::ParseGenes(a.genes, run.robot->controller.genes.size());
    if (!genes.ok()) return Fail(genes.status(), 2);
    if (a.out.empty()) return Fail(absl::InvalidArgumentError("trajectory needs --out FILE.csv"), 2);
    if (auto s = simtool::GenericTrajectory(run, *genes, a.out); !s.ok())
      return Fail(s, s.code() == absl::StatusCode::kAborted ? 1 : 2);
    std::cout << a.out << "\n";
    return 0;
  }
  if (a.cmd != "calibration-eval")
    return Fail(absl::InvalidArgumentError("unknown command '" + a.cmd + "'"), 2);
  auto opts = simtool::ParseOptions(a.options);
  if (!opts.ok()) return Fail(opts.status(), 2);
  auto pars = simtool::ParseOverrides(a.params);
  if (!pars.ok()) return Fail(pars.status(), 2);
  auto report = simtool::GenericCalibrationEval(
      run, a.recordings, *opts, std::map<std::string, double>(pars->begin(), pars->end()), a.out_dir);
  if (!report.ok()) return Fail(report.status(), 2);
  std::cout << *report << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  a.scales = "0.5,2,16";
  a.periods = "0.2,2.0,19";
  a.engine = "ode";
  std::string params_path, error_kind, metric, max_shift;
  a.threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  core::Flags flags(
      "gaitforge-sim trajectory|period-sweep|wave|calibration-eval|track|learn-parameters|plan "
      "[flags]",
      "One-shot simulations of a robot on the generic builder (--robot; calibration-eval and\n"
      "learn-parameters default to the robot their first recording's sidecar names), with\n"
      "the same model build as the workers.\n"
      "  trajectory    --genes G --out FILE.csv: the robot's channels over settle + measured\n"
      "                cycles from rest, as a recording CSV (+ .json); or --inputs IN.csv\n"
      "                --out FILE.csv: driven by recorded actuator inputs (a playback)\n"
      "  period-sweep  --genes G: distance per cycle with the period scaled (--scales), JSON\n"
      "  wave          paper 000's travelling waves over periods (--periods), JSON\n"
      "  calibration-eval  --recordings A.csv,B.csv [--set ...]: the calibration objective's\n"
      "                errors against recordings, and the simulated channels (--out-dir), JSON\n"
      "  track         --path PATH.csv [--feedforward model --model-set ...]: the robot (with\n"
      "                --set: the plant) follows a path with its tracking PID; errors as JSON,\n"
      "                every control tick as CSV (--out)\n"
      "  learn-parameters --recordings A.csv,... --params P,... --features tip.x,... --out\n"
      "                NET.json: paper 004's adaptive model (parameters fitted per playback\n"
      "                recording, an MLP from state to them), JSON\n"
      "  plan          --recordings A.csv,... --report diagnosis.json: the gaits whose\n"
      "                recordings would separate the diagnosis's explanations, JSON\n"
      "                (gaitforge diagnose plan runs it; docs/diagnosis.md)");
  flags.Add("robot", &a.robot,
            "the robot: a built-in's name or a descriptor file (docs/robots.md); required but "
            "for calibration-eval and learn-parameters (default: the recordings' robot)");
  std::string count_text;
  flags.Add("count", &count_text,
            "another resolution of the robot: its counts NAME=N,... (docs/robots.md, \"Counts and "
            "repeats\"; the arm: lumps=12)");
  flags.Add("params", &params_path, "a descriptor file, as --robot (kept for old scripts)");
  flags.Add("engine", &a.engine,
            "trajectory: ode (the studies' build) or mujoco (an independent build of the same "
            "descriptor, workers/models/mujoco/)");
  flags.Add("genes", &a.genes,
            "the controller's genes, comma separated, in its order (gaitforge robots show NAME)");
  flags.Add("out", &a.out, "trajectory: CSV file to write");
  flags.Add("inputs", &a.inputs,
            "trajectory: a CSV of t and every actuator's input (rod1.force, ...) that drives the "
            "robot instead of --genes; writes a playback recording");
  flags.Add("rate", &a.rate, "trajectory, calibration-eval: sampling rate, Hz (1..10000)");
  flags.Add("cycles", &a.cycles, "measured gait cycles (1..200)");
  flags.Add("settle", &a.settle, "gait cycles from rest before measuring (0..50)");
  flags.Add("scales", &a.scales, "period-sweep: FROM,TO,COUNT multipliers (geometric)");
  flags.Add("periods", &a.periods, "wave: FROM,TO,COUNT periods in s (linear)");
  flags.Add("threads", &a.threads, "simulations run at once");
  flags.Add("set", &a.set,
            "parameter overrides NAME=VALUE,... (names: docs/objectives.md, e.g. "
            "actuators.force_n, scale.link_stiffness); applied in order");
  flags.Add("recordings", &a.recordings,
            "calibration-eval, learn-parameters: recording CSVs, comma separated");
  flags.Add("error", &error_kind, "calibration-eval: shape, pointwise, stats or acceleration (default shape)");
  flags.Add("metric", &metric, "calibration-eval: rmse or mae (default rmse)");
  flags.Add("max-shift", &max_shift,
            "calibration-eval: max_shift_samples, 0..1000 (default 10); plan: the time shifts (in "
            "samples) a comparison of two explanations may absorb, 0..1000 (default 10)");
  flags.Add("options", &a.options,
            "calibration-eval: the objective's options NAME=VALUE;... (error, metric, channels)");
  flags.Add("objective-params", &a.params,
            "calibration-eval: the objective's params NAME=VALUE,... (max_shift_samples, ...)");
  flags.Add("path", &a.track.path, "track: a path recording (CSV + .json, command kind path)");
  flags.Add("feedforward", &a.track.feedforward,
            "track: none (the PID alone) or model (plus the feed-forward learned on the model "
            "--model-set describes)");
  flags.Add("model-set", &a.track.model_set,
            "track: the model's parameter overrides NAME=VALUE,... (default: the descriptor's)");
  flags.Add("ff-iterations", &a.track.ff_iterations,
            "track: model runs that learn the feed-forward (1..1000, default 20)");
  flags.AddBool("open-loop", &a.open_loop, "track: the feed-forward alone, no PID");
  flags.Add("learned", &a.learned,
            "trajectory, track, learn-parameters: an MLP file (docs/learned-models.md) that sets "
            "the robot's parameters from its state every step");
  flags.Add("model-learned", &a.track.model_learned,
            "track: an MLP file (learn-parameters) that sets the model's parameters from its "
            "state every step: the adaptive model");
  flags.Add("params-learned", &a.learn.params, "learn-parameters: the parameters to learn, comma separated");
  flags.Add("features", &a.learn.features,
            "learn-parameters: the MLP's inputs, channels (.rate: their rate), comma separated");
  flags.Add("held-out", &a.learn.held_out, "learn-parameters: playback recordings to compare the models on");
  flags.Add("evaluations", &a.learn.evaluations, "learn-parameters: playbacks per fit (5..100000, default 150)");
  flags.Add("epochs", &a.learn.epochs, "learn-parameters: MLP training epochs (default 5000)");
  flags.Add("hidden", &a.learn.hidden, "learn-parameters: hidden units (default 5, paper 004)");
  diagnosis::plan::AddFlags(flags, &a.plan.options, "plan");
  flags.Add("channels", &a.plan.channels,
            "plan: compared channels, comma separated (default: every one the recordings and the "
            "model both have)");
  flags.Add("out-dir", &a.out_dir, "calibration-eval: write each recording's simulated channels here");
  if (auto s = flags.Parse(argc, argv); !s.ok()) return Fail(s, 2);
  if (flags.help_requested() || flags.positional().size() != 1) {
    std::cout << flags.Help();
    return flags.help_requested() ? 0 : 2;
  }
  a.cmd = flags.positional()[0];
  if (a.cycles < 1 || a.cycles > 200 || a.settle < 0 || a.settle > 50 ||
      !(a.rate >= 1 && a.rate <= 10000) || a.threads < 1 || a.threads > 256)
    return Fail(absl::InvalidArgumentError("--cycles in [1, 200], --settle in [0, 50], --rate in "
                                           "[1, 10000], --threads in [1, 256]"),
                2);
  if (a.robot.empty()) a.robot = params_path;
  if (a.robot.empty()) {
    auto robot = DefaultRobot(a.cmd, a.recordings);
    if (!robot.ok()) return Fail(robot.status(), 2);
    a.robot = *robot;
  }
  for (const std::string& item :
       std::vector<std::string>(absl::StrSplit(count_text, ',', absl::SkipEmpty()))) {
    const std::vector<std::string> kv = absl::StrSplit(item, '=');
    int n = 0;
    if (kv.size() != 2 || !absl::SimpleAtoi(kv[1], &n))
      return Fail(absl::InvalidArgumentError("--count: expected NAME=N,... (a whole N), got '" + item + "'"), 2);
    a.counts.emplace_back(kv[0], n);
  }
  if (a.cmd == "plan" && !max_shift.empty() && !absl::SimpleAtoi(max_shift, &a.plan.options.max_shift))
    return Fail(absl::InvalidArgumentError("--max-shift: expected a whole number, got '" + max_shift + "'"), 2);
  // The named flags win over the same names in --options and --objective-params.
  if (!error_kind.empty()) a.options += ";error=" + error_kind;
  if (!metric.empty()) a.options += ";metric=" + metric;
  if (!max_shift.empty()) {
    char* end = nullptr;
    std::strtod(max_shift.c_str(), &end);
    if (max_shift.empty() || *end)
      return Fail(absl::InvalidArgumentError("--max-shift: expected a number, got '" + max_shift + "'"), 2);
    // First: of a name given twice, the first is kept.
    a.params = "max_shift_samples=" + max_shift + (a.params.empty() ? "" : ",") + a.params;
  }
  return Run(a);
}
