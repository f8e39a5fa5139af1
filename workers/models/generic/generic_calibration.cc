// "robot.calibration" (generic_calibration.h).
#include "workers/models/generic/generic_calibration.h"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "robots/controllers.h"
#include "robots/registry.h"
#include "workers/models/generic/generic_gait.h"
#include "workers/models/generic/generic_playback.h"
#include "workers/objectives/recording_comparison.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::generic {
namespace {

absl::StatusOr<calibration::Comparison> Compare(const robots::RobotDescriptor& d,
                                                const ParamValues& values,
                                                const recording::Recording& rec, double offset,
                                                const calibration::CompareSettings& s) {
  if (rec.meta.robot != d.name)
    return absl::InvalidArgumentError(
        absl::StrCat("a recording of robot '", rec.meta.robot, "', not ", d.name));
  if (rec.meta.command_kind == "path")
    return absl::InvalidArgumentError(
        "a path recording (command kind path) is a reference for tracking, not a recording "
        "of the robot moving: calibrate against gait or playback recordings");
  if (rec.meta.command_kind == "playback")
    return calibration::CompareRecording(rec, 0, offset, s, [&](double duration, double rate_hz) {
      return SimulatePlayback(d, values, rec, offset, duration, rate_hz, s.timestep_s);
    });
  if (rec.meta.genes.size() != d.controller.genes.size())
    return absl::InvalidArgumentError(absl::StrCat("meta.genes: ", d.name, " takes ",
                                                   d.controller.genes.size(), " genes, got ",
                                                   rec.meta.genes.size()));
  const double period = robots::FindControllerKind(d.controller.kind)->period_s(rec.meta.genes);
  if (!(period > 0) || !std::isfinite(period))
    return absl::InvalidArgumentError(absl::StrCat("meta.genes give a gait period of ", period, " s"));
  return calibration::CompareRecording(rec, period, offset, s, [&](double duration, double rate_hz) {
    const int cycles = static_cast<int>(std::llround(duration / period));
    return SimulateChannels(d, values, rec.meta.genes, cycles, rate_hz, s.timestep_s);
  });
}

}  // namespace

objectives::EvalResult RobotCalibrationObjective::Evaluate(const objectives::EvalInput& in) const {
  sim::InitThread();
  objectives::EvalResult r;
  auto robot = robots::ResolveRobot(in.robot, in.robot_descriptor);
  if (!robot.ok()) {
    r.reason = "robot: " + std::string(robot.status().message());
    return r;
  }
  const robots::RobotDescriptor& d = **robot;
  ParamValues values(d);
  auto settings = calibration::ParseCompareSettings(
      in, static_cast<int>(values("simulation.settle_cycles")), d.Channels(), d.name);
  if (!settings.ok()) {
    r.reason = std::string(settings.status().message());
    return r;
  }
  if (in.gene_names.size() != in.genes.size()) {
    r.reason = absl::StrCat(kRobotCalibrationName, " needs a name for every gene: ",
                            in.genes.size(), " genes, ", in.gene_names.size(), " names");
    return r;
  }
  double offset = 0;
  for (size_t i = 0; i < in.genes.size(); ++i) {
    const std::string& name = in.gene_names[i];
    if (!std::isfinite(in.genes[i])) {
      r.reason = absl::StrCat("gene ", i, " (", name, ") is not finite");
      return r;
    }
    if (name == calibration::kTimeOffsetGene) {
      offset = in.genes[i];
    } else if (absl::Status st = values.Set(name, in.genes[i]); !st.ok()) {
      r.reason = absl::StrCat("gene ", i, ": ", st.message());
      return r;
    }
  }
  if (settings->timestep_s <= 0) settings->timestep_s = values("simulation.timestep_s");
  return calibration::CompareAll(in, *settings, kRobotCalibrationName,
                                 [&](const recording::Recording& rec) {
                                   return Compare(d, values, rec, offset, *settings);
                                 });
}

}  // namespace gaitforge::generic
