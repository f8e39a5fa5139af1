#include "workers/models/caterpillar/calibration_objective.h"

#include <cmath>
#include <string>

#include "absl/status/statusor.h"
#include "absl/strings/str_cat.h"
#include "workers/models/caterpillar/caterpillar_eval.h"
#include "workers/models/caterpillar/gait.h"
#include "workers/models/caterpillar/param_overrides.h"
#include "workers/objectives/recording_comparison.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::caterpillar {

calibration::Trajectory MarkerChannels(const MarkerTrajectory& m) {
  calibration::Trajectory t;
  t.t = m.t;
  for (int k = 0; k < 6; ++k) {
    const std::string name = absl::StrCat("m", k + 1, ".");
    for (int a = 0; a < 3; ++a) {
      t.channels.push_back(name + "xyz"[a]);
      t.columns.push_back(a == 0 ? m.x[k] : a == 1 ? m.y[k] : m.z[k]);
    }
  }
  return t;
}

namespace {

absl::StatusOr<calibration::Comparison> Compare(const CaterpillarParams& params,
                                                const recording::Recording& rec, double offset,
                                                const calibration::CompareSettings& s) {
  if (!rec.meta.robot.empty() && rec.meta.robot != "caterpillar")
    return absl::InvalidArgumentError(
        absl::StrCat("a recording of robot '", rec.meta.robot, "', not the caterpillar"));
  auto gait = Gait::FromGenes(rec.meta.genes);
  if (!gait.ok())
    return absl::InvalidArgumentError(absl::StrCat("meta.genes: ", gait.status().message()));
  return calibration::CompareRecording(
      rec, gait->period_s(), offset, s, [&](int cycles, double rate_hz) {
        EvalOptions options;
        options.settle_cycles = 0;
        options.measured_cycles = cycles;
        options.timestep_s = s.timestep_s;
        options.marker_rate_hz = rate_hz;
        const GaitEvaluation e = EvaluateGait(params, *gait, options);
        calibration::SimRun run;
        run.valid = e.valid;
        run.reason = e.reason;
        run.simulated_s = e.simulated_s;
        if (e.valid) run.trajectory = MarkerChannels(e.markers);
        return run;
      });
}

}  // namespace

objectives::EvalResult CalibrationObjective::Evaluate(const objectives::EvalInput& in) const {
  sim::InitThread();  // once per thread; later calls are free
  objectives::EvalResult r;
  auto settings = calibration::ParseCompareSettings(
      in, 2, CaterpillarDescriptor().Channels(), "the caterpillar");
  if (!settings.ok()) {
    r.reason = std::string(settings.status().message());
    return r;
  }
  if (in.gene_names.size() != in.genes.size()) {
    r.reason =
        absl::StrCat("caterpillar.calibration needs a name for every gene: ", in.genes.size(),
                     " genes, ", in.gene_names.size(), " names");
    return r;
  }
  CaterpillarParams params = params_;
  double offset = 0;
  for (size_t i = 0; i < in.genes.size(); ++i) {
    const std::string& name = in.gene_names[i];
    if (name == kTimeOffsetParam) {
      if (!std::isfinite(in.genes[i])) {
        r.reason = absl::StrCat("gene ", i, " (", name, ") is not finite");
        return r;
      }
      offset = in.genes[i];
      continue;
    }
    if (absl::Status st = SetParam(params, name, in.genes[i]); !st.ok()) {
      r.reason = absl::StrCat("gene ", i, ": ", st.message());
      return r;
    }
  }
  // Without an explicit timestep_ms, the (possibly overridden) parameters' own timestep.
  if (settings->timestep_s <= 0) settings->timestep_s = params.simulation.timestep_s;
  return calibration::CompareAll(in, *settings, "caterpillar.calibration",
                                 [&](const recording::Recording& rec) {
                                   return Compare(params, rec, offset, *settings);
                                 });
}

void RegisterCaterpillarCalibration(objectives::ObjectiveRegistry& registry) {
  registry.Register(kCalibrationObjectiveName,
                    std::make_shared<CalibrationObjective>(DefaultCaterpillarParams()));
}

}  // namespace gaitforge::caterpillar
