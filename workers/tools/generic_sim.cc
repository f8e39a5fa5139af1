// gaitforge-sim for generic robots (generic_sim.h).
#include "workers/tools/generic_sim.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_split.h"
#include "robots/controllers.h"
#include "services/recording/recording.h"
#include "workers/models/generic/generic_calibration.h"
#include "workers/models/generic/generic_gait.h"
#include "workers/models/generic/generic_playback.h"
#include "workers/objectives/calibration_error.h"
#include "workers/models/mujoco/mujoco_world.h"
#include "workers/objectives/recording_comparison.h"
#include "workers/sim/ode_runtime.h"
#include "workers/tools/sim_tool.h"

namespace gaitforge::simtool {
namespace {

std::string MetricsJson(const objectives::EvalResult& r) {
  std::string json;
  int k = 0;
  for (const auto& [name, value] : r.metrics)
    absl::StrAppend(&json, k++ ? ", " : "", "\"", name, "\": ", absl::StrFormat("%.9g", value));
  return json;
}

}  // namespace

absl::StatusOr<learned::Mlp> ReadMlp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return absl::NotFoundError(absl::StrCat("cannot read the learned model ", path));
  std::stringstream text;
  text << in.rdbuf();
  return learned::Mlp::FromJson(text.str(), path);
}

absl::StatusOr<generic::ParamValues> RunValues(const GenericRun& run) {
  generic::ParamValues v(*run.robot);
  for (const auto& [name, value] : run.overrides) {
    if (name == calibration::kTimeOffsetGene) continue;
    if (auto s = v.Set(name, value); !s.ok()) return absl::InvalidArgumentError(absl::StrCat("--set ", s.message()));
  }
  if (!run.learned.empty()) {
    auto mlp = ReadMlp(run.learned);
    if (!mlp.ok()) return mlp.status();
    v.SetLearned(std::make_shared<learned::Mlp>(*std::move(mlp)));
  }
  return v;
}

absl::StatusOr<recording::Recording> ReadRecording(const std::string& path, const GenericRun& run) {
  std::ifstream csv_in(path, std::ios::binary), side_in(path + ".json", std::ios::binary);
  if (!csv_in || !side_in)
    return absl::NotFoundError(absl::StrCat("cannot read ", path, " and ", path, ".json"));
  std::stringstream csv, side;
  csv << csv_in.rdbuf();
  side << side_in.rdbuf();
  return recording::ParseRecording(csv.str(), side.str(), path, path + ".json", {}, run.robot);
}

absl::Status GenericTrajectory(const GenericRun& run, const std::vector<double>& genes,
                               const std::string& out) {
  const robots::RobotDescriptor& d = *run.robot;
  if (genes.size() != d.controller.genes.size())
    return absl::InvalidArgumentError(absl::StrCat("--genes: ", d.name, " takes ",
                                                   d.controller.genes.size(), " genes, got ",
                                                   genes.size()));
  auto values = RunValues(run);
  if (!values.ok()) return values.status();
  if (run.engine != "ode" && run.engine != "mujoco")
    return absl::InvalidArgumentError("--engine " + run.engine + ": one of ode, mujoco");
  sim::InitThread();
  const auto sim = generic::SimulateChannels(d, *values, genes, run.cycles, run.rate_hz, 0,
                                             run.engine == "mujoco" ? mujoco::Engine() : nullptr,
                                             run.settle_cycles);
  if (!sim.valid) return absl::AbortedError("the simulation failed: " + sim.reason);
  return WriteChannels(sim.trajectory, out, d.name, run.robot_path, genes,
                       run.engine == "mujoco" ? "simulated by gaitforge-sim, MuJoCo build"
                                              : "simulated by gaitforge-sim",
                       run.overrides);
}

absl::Status GenericPlayback(const GenericRun& run, const std::string& inputs,
                             const std::string& out) {
  const robots::RobotDescriptor& d = *run.robot;
  std::ifstream in(inputs, std::ios::binary);
  if (!in) return absl::NotFoundError(absl::StrCat("--inputs: cannot read ", inputs));
  std::stringstream csv;
  csv << in.rdbuf();
  const std::string sidecar =
      absl::StrCat("{\"robot\": \"", JsonEscape(d.name), "\", \"command\": {\"kind\": \"playback\"}}");
  auto rec = recording::ParseRecording(csv.str(), sidecar, inputs, inputs + " (a playback)", {},
                                       run.robot);
  if (!rec.ok()) return rec.status();
  auto values = RunValues(run);
  if (!values.ok()) return values.status();
  double offset = 0;
  for (const auto& [name, value] : run.overrides)
    if (name == calibration::kTimeOffsetGene) offset = value;
  sim::InitThread();
  auto sim = generic::SimulatePlayback(d, *values, *rec, offset, rec->t.back() + offset + 1e-9,
                                       run.rate_hz);
  if (!sim.valid) return absl::AbortedError("the simulation failed: " + sim.reason);
  calibration::Trajectory& tr = sim.trajectory;
  for (const std::string& input : d.InputChannels()) {
    const int c = rec->ChannelIndex(input);
    tr.channels.push_back(input);
    tr.columns.emplace_back();
    for (double t : tr.t) tr.columns.back().push_back(calibration::Interpolate(rec->t, rec->columns[c], t - offset));
  }
  return WriteChannels(tr, out, d.name, run.robot_path, {}, "simulated by gaitforge-sim (playback)",
                       run.overrides, true);
}

absl::StatusOr<std::string> GenericCalibrationEval(const GenericRun& run,
                                                   const std::string& recordings,
                                                   const std::map<std::string, std::string>& options,
                                                   const std::map<std::string, double>& params,
                                                   const std::string& out_dir) {
  double offset = 0;
  for (const auto& [name, value] : run.overrides)
    if (name == calibration::kTimeOffsetGene) offset = value;
  if (!out_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(out_dir, ec);
    if (ec) return absl::InvalidArgumentError(absl::StrCat("--out-dir ", out_dir, ": ", ec.message()));
  }
  auto values = RunValues(run);
  if (!values.ok()) return values.status();
  const generic::RobotCalibrationObjective objective;
  std::string json = "{\"recordings\": [";
  int i = 0;
  for (const auto& part : absl::StrSplit(recordings, ',', absl::SkipEmpty())) {
    const std::string path(part);
    auto rec = ReadRecording(path, run);
    if (!rec.ok()) return rec.status();
    objectives::EvalInput in;
    for (const auto& [name, value] : run.overrides) {
      in.gene_names.push_back(name);
      in.genes.push_back(value);
    }
    in.lo.assign(in.genes.size(), -1e300);
    in.hi.assign(in.genes.size(), 1e300);
    in.options = options;
    in.params = params;
    in.robot = run.robot->name;
    in.robot_descriptor = run.robot_text;
    in.recordings.push_back(std::make_shared<const recording::Recording>(*rec));
    sim::InitThread();
    const auto r = objectives::EvaluateSafely(objective, in);
    absl::StrAppend(&json, i ? ",\n " : "\n ", "{\"file\": \"", JsonEscape(path),
                    "\", \"time_offset_s\": ", absl::StrFormat("%.9g", offset), ", \"valid\": ",
                    r.valid ? "true" : "false", ", \"reason\": \"", JsonEscape(r.reason),
                    "\", \"metrics\": {", MetricsJson(r), "}");
    if (!out_dir.empty() && r.valid) {
      // The recording's command with the same overrides, channels over the recording's span.
      const bool playback = rec->meta.command_kind == "playback";
      const double period =
          playback ? 0 : robots::FindControllerKind(run.robot->controller.kind)->period_s(rec->meta.genes);
      const auto sim =
          playback ? generic::SimulatePlayback(*run.robot, *values, *rec, offset, rec->t.back() + offset,
                                               run.rate_hz)
                   : generic::SimulateChannels(
                         *run.robot, *values, rec->meta.genes,
                         static_cast<int>(std::ceil((rec->t.back() + 0.5) / period)) + 1, run.rate_hz);
      if (sim.valid) {
        const std::string sim_path = absl::StrCat(out_dir, "/sim-", i, ".csv");
        if (auto s = WriteChannels(sim.trajectory, sim_path, run.robot->name, run.robot_path,
                                   rec->meta.genes, "calibration-eval");
            !s.ok())
          return s;
        absl::StrAppend(&json, ", \"sim\": \"", JsonEscape(sim_path), "\"");
      }
    }
    absl::StrAppend(&json, "}");
    ++i;
  }
  return json + "\n]}";
}

}  // namespace gaitforge::simtool
