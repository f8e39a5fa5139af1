// gaitforge-sim: one-shot caterpillar simulations with the workers' own model build.
//   trajectory    markers of one gait as a recording CSV (+ JSON sidecar)
//   period-sweep  distance per cycle as a gait's period is scaled (paper 000, Fig. 13)
//   wave          the travelling-wave baseline over periods (paper 000, Fig. 14)
//   calibration-eval  errors of the model (with --set overrides) against recordings, and
//                 the simulated markers of each recording's gait, for calibration reports
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <thread>

#include "absl/strings/str_cat.h"
#include "robots/registry.h"

#include "services/core/flags.h"
#include "workers/models/caterpillar/caterpillar_params.h"
#include "workers/sim/ode_runtime.h"
#include "workers/models/caterpillar/param_overrides.h"
#include "workers/tools/generic_sim.h"
#include "workers/tools/sim_tool.h"

using namespace gaitforge;

namespace {

// The descriptor a --robot names: a file's text, or a built-in robot's.
absl::StatusOr<std::pair<std::string, std::string>> RobotText(const std::string& arg) {
  if (std::filesystem::is_regular_file(arg)) {
    std::ifstream in(arg, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    return std::make_pair(arg, text.str());
  }
  if (robots::FindRobot(arg) == nullptr)
    return absl::NotFoundError(absl::StrCat("--robot ", arg,
                                            ": neither a descriptor file nor a built-in robot"));
  return std::make_pair(std::string(), std::string(robots::BuiltinText(arg)));
}

// trajectory and calibration-eval of a robot on the generic builder; an exit code.
int RunGenericCommand(const std::string& cmd, const std::string& robot_arg,
                      const std::string& genes_text, const std::string& out,
                      const std::string& set_text, const std::string& recordings,
                      const std::string& options_text, const std::string& params_text,
                      const std::string& out_dir, double rate, int cycles, int settle,
                      const std::string& engine) {
  auto fail = [](const absl::Status& s, int code) {
    std::cerr << "gaitforge-sim: " << s.message() << "\n";
    return code;
  };
  auto text = RobotText(robot_arg);
  if (!text.ok()) return fail(text.status(), 2);
  auto robot = robots::ResolveRobot("", text->second);
  if (!robot.ok()) return fail(robot.status(), 2);
  if ((*robot)->model != "generic")
    return fail(absl::InvalidArgumentError(absl::StrCat(
                    "--robot ", robot_arg, " has model ", (*robot)->model,
                    "; --robot takes robots on the generic builder (the caterpillar: no --robot)")),
                2);
  if (cmd != "trajectory" && cmd != "calibration-eval")
    return fail(absl::InvalidArgumentError(cmd + " is the caterpillar's; with --robot: "
                                                 "trajectory or calibration-eval"), 2);
  simtool::GenericRun run;
  run.robot = robot->get();
  run.robot_path = text->first;
  run.robot_text = text->second;
  run.rate_hz = rate;
  run.cycles = cycles;
  run.settle_cycles = settle;
  run.engine = engine;
  const double h = run.robot->Value("simulation.timestep_s");
  const double steps = 1.0 / (rate * h);
  if (!(rate > 0) || std::abs(steps - std::round(steps)) > 1e-9 || std::round(steps) < 1)
    return fail(absl::InvalidArgumentError(absl::StrCat(
                    "--rate ", rate, " Hz is not a whole number of ", h, " s steps")), 2);
  auto overrides = simtool::ParseOverrides(set_text);
  if (!overrides.ok()) return fail(overrides.status(), 2);
  run.overrides = *overrides;
  sim::InitProcess();
  if (cmd == "trajectory") {
    auto genes = simtool::ParseGenes(genes_text, run.robot->controller.genes.size());
    if (!genes.ok()) return fail(genes.status(), 2);
    if (out.empty()) return fail(absl::InvalidArgumentError("trajectory needs --out FILE.csv"), 2);
    if (auto s = simtool::GenericTrajectory(run, *genes, out); !s.ok())
      return fail(s, s.code() == absl::StatusCode::kAborted ? 1 : 2);
    std::cout << out << "\n";
    return 0;
  }
  auto opts = simtool::ParseOptions(options_text);
  if (!opts.ok()) return fail(opts.status(), 2);
  auto pars = simtool::ParseOverrides(params_text);
  if (!pars.ok()) return fail(pars.status(), 2);
  auto report = simtool::GenericCalibrationEval(
      run, recordings, *opts, std::map<std::string, double>(pars->begin(), pars->end()), out_dir);
  if (!report.ok()) return fail(report.status(), 2);
  std::cout << *report << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::string params_path;  // empty: the built-in robots/caterpillar/robot.yaml
  std::string genes_text, out, scales_text = "0.5,2,16", periods_text = "0.2,2.0,19";
  std::string set_text, recordings_text, out_dir, options_text, objective_params_text;
  std::string error_kind, metric, max_shift;  // empty: from --options/--objective-params
  double rate = 100;
  int cycles = 10, settle = 2;
  int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  core::Flags flags(
      "gaitforge-sim trajectory|period-sweep|wave [flags]",
      "One-shot simulations of the ODE caterpillar, or of any robot on the generic builder\n"
      "(--robot), with the same model build as the workers.\n"
      "  trajectory    --genes G --out FILE.csv: markers m1..m6 as a recording CSV (+ .json)\n"
      "  period-sweep  --genes G: distance per cycle with the period scaled (--scales), JSON\n"
      "  wave          travelling-wave gait over periods (--periods), JSON\n"
      "  calibration-eval  --recordings A.csv,B.csv [--set ...]: the calibration objective's\n"
      "                errors against recordings, and the simulated markers (--out-dir), JSON");
  flags.Add("params", &params_path, "caterpillar descriptor file (a copy of robots/caterpillar/robot.yaml)");
  std::string robot_arg;
  flags.Add("robot", &robot_arg,
            "a robot on the generic builder: a built-in's name or a descriptor file "
            "(trajectory, calibration-eval; docs/robots.md)");
  std::string engine = "ode";
  flags.Add("engine", &engine,
            "with --robot, trajectory: ode (the studies' build) or mujoco (an independent build "
            "of the same descriptor, workers/models/mujoco/)");
  flags.Add("genes", &genes_text, "13 numbers a_T1..a_B3 d_T1..d_B3 T, comma separated");
  flags.Add("out", &out, "trajectory: CSV file to write");
  flags.Add("rate", &rate, "trajectory: marker sampling rate, Hz (1..10000)");
  flags.Add("cycles", &cycles, "measured gait cycles (1..200)");
  flags.Add("settle", &settle, "gait cycles from rest before measuring (0..50)");
  flags.Add("scales", &scales_text, "period-sweep: FROM,TO,COUNT multipliers (geometric)");
  flags.Add("periods", &periods_text, "wave: FROM,TO,COUNT periods in s (linear)");
  flags.Add("threads", &threads, "simulations run at once");
  flags.Add("set", &set_text,
            "parameter overrides NAME=VALUE,... (names: docs/objectives.md, e.g. "
            "actuators.force_n, scale.link_stiffness); applied in order");
  flags.Add("recordings", &recordings_text, "calibration-eval: recording CSVs, comma separated");
  flags.Add("error", &error_kind, "calibration-eval: shape, pointwise or stats (default shape)");
  flags.Add("metric", &metric, "calibration-eval: rmse or mae (default rmse)");
  flags.Add("max-shift", &max_shift,
            "calibration-eval: max_shift_samples, 0..1000 (default 10)");
  flags.Add("options", &options_text,
            "calibration-eval: the objective's options NAME=VALUE;... (error, metric, channels)");
  flags.Add("objective-params", &objective_params_text,
            "calibration-eval: the objective's params NAME=VALUE,... (max_shift_samples, ...)");
  flags.Add("out-dir", &out_dir, "calibration-eval: write each recording's simulated markers here");
  if (auto s = flags.Parse(argc, argv); !s.ok()) {
    std::cerr << "gaitforge-sim: " << s.message() << "\n";
    return 2;
  }
  if (flags.help_requested() || flags.positional().size() != 1) {
    std::cout << flags.Help();
    return flags.help_requested() ? 0 : 2;
  }
  const std::string cmd = flags.positional()[0];
  if (!robot_arg.empty()) {
    return RunGenericCommand(cmd, robot_arg, genes_text, out, set_text, recordings_text,
                             options_text, objective_params_text, out_dir, rate, cycles, settle,
                             engine);
  }
  if (cycles < 1 || cycles > 200 || settle < 0 || settle > 50 || !(rate >= 1 && rate <= 10000) ||
      threads < 1 || threads > 256) {
    std::cerr << "gaitforge-sim: --cycles in [1, 200], --settle in [0, 50], --rate in [1, 10000], "
                 "--threads in [1, 256]\n";
    return 2;
  }
  auto params = params_path.empty()
                    ? absl::StatusOr<caterpillar::CaterpillarParams>(
                          caterpillar::DefaultCaterpillarParams())
                    : caterpillar::LoadCaterpillarParams(params_path);
  if (!params.ok()) {
    std::cerr << "gaitforge-sim: " << params.status().message() << "\n";
    return 2;
  }
  auto overrides = simtool::ParseOverrides(set_text);
  if (!overrides.ok()) {
    std::cerr << "gaitforge-sim: --set " << overrides.status().message() << "\n";
    return 2;
  }
  if (cmd != "calibration-eval") {
    for (const auto& [name, value] : *overrides) {
      if (auto s = caterpillar::SetParam(*params, name, value); !s.ok()) {
        std::cerr << "gaitforge-sim: --set " << s.message() << "\n";
        return 2;
      }
    }
  }
  if (cmd == "trajectory" || cmd == "calibration-eval") {
    // Markers are sampled on simulation steps: the interval must be a whole number of them.
    const double steps = 1.0 / (rate * params->simulation.timestep_s);
    if (std::abs(steps - std::round(steps)) > 1e-9 || std::round(steps) < 1) {
      std::cerr << "gaitforge-sim: --rate " << rate << " Hz is not a whole number of "
                << params->simulation.timestep_s << " s steps; use 1000 / k Hz (e.g. 100, 200, "
                   "250, 500)\n";
      return 2;
    }
  }
  sim::InitProcess();
  caterpillar::EvalOptions options;
  options.measured_cycles = cycles;
  options.settle_cycles = settle;

  if (cmd == "calibration-eval") {
    auto opts = simtool::ParseOptions(options_text);
    if (!opts.ok()) {
      std::cerr << "gaitforge-sim: --options " << opts.status().message() << "\n";
      return 2;
    }
    auto pars = simtool::ParseOverrides(objective_params_text);
    if (!pars.ok()) {
      std::cerr << "gaitforge-sim: --objective-params " << pars.status().message() << "\n";
      return 2;
    }
    std::map<std::string, double> objective_params(pars->begin(), pars->end());
    // The named flags win over the same names in --options and --objective-params; a bad
    // value makes every result invalid with the objective's reason.
    if (!error_kind.empty()) (*opts)["error"] = error_kind;
    if (!metric.empty()) (*opts)["metric"] = metric;
    if (!max_shift.empty()) {
      auto shift = simtool::ParseOverrides("max_shift_samples=" + max_shift);
      if (!shift.ok()) {
        std::cerr << "gaitforge-sim: --max-shift: expected a number, got '" << max_shift << "'\n";
        return 2;
      }
      objective_params["max_shift_samples"] = shift->front().second;
    }
    auto report = simtool::CalibrationEval(*params, *overrides, recordings_text, *opts,
                                           objective_params, out_dir, rate);
    if (!report.ok()) {
      std::cerr << "gaitforge-sim: " << report.status().message() << "\n";
      return 2;
    }
    std::cout << *report << "\n";
    return 0;
  }
  if (cmd == "wave") {
    auto periods = simtool::ParseRange(periods_text, false);
    if (!periods.ok()) {
      std::cerr << "gaitforge-sim: --periods " << periods.status().message() << "\n";
      return 2;
    }
    std::cout << simtool::SweepJson(simtool::WaveSweep(*params, *periods, options, threads))
              << "\n";
    return 0;
  }
  auto genes = simtool::ParseGenes(genes_text);
  if (!genes.ok()) {
    std::cerr << "gaitforge-sim: " << genes.status().message() << "\n";
    return 2;
  }
  if (cmd == "period-sweep") {
    auto scales = simtool::ParseRange(scales_text, true);
    if (!scales.ok()) {
      std::cerr << "gaitforge-sim: --scales " << scales.status().message() << "\n";
      return 2;
    }
    std::cout << simtool::SweepJson(
                     simtool::PeriodSweep(*params, *genes, *scales, options, threads))
              << "\n";
    return 0;
  }
  if (cmd == "trajectory") {
    if (out.empty()) {
      std::cerr << "gaitforge-sim: trajectory needs --out FILE.csv\n";
      return 2;
    }
    auto gait = caterpillar::Gait::FromGenes(*genes);
    if (!gait.ok()) {
      std::cerr << "gaitforge-sim: " << gait.status().message() << "\n";
      return 2;
    }
    options.marker_rate_hz = rate;
    sim::InitThread();
    const auto e = caterpillar::EvaluateGait(*params, *gait, options);
    if (!e.valid) {
      std::cerr << "gaitforge-sim: the simulation diverged: " << e.reason << "\n";
      return 1;
    }
    if (auto s = simtool::WriteRecording(e.markers, out,
                                         params_path.empty() ? "robots/caterpillar/robot.yaml"
                                                             : params_path,
                                         *genes,
                                         "simulated by gaitforge-sim", *overrides);
        !s.ok()) {
      std::cerr << "gaitforge-sim: " << s.message() << "\n";
      return 1;
    }
    std::cout << out << "\n";
    return 0;
  }
  std::cerr << "gaitforge-sim: unknown command '" << cmd << "'\n";
  return 2;
}
