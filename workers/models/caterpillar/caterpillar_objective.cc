#include "workers/models/caterpillar/caterpillar_objective.h"

#include <cstdlib>

#include "absl/strings/str_split.h"
#include "workers/models/caterpillar/param_overrides.h"
#include "workers/objectives/overrides.h"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "workers/models/caterpillar/caterpillar_eval.h"
#include "workers/models/caterpillar/gait.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::caterpillar {
namespace {

}  // namespace

objectives::EvalResult CaterpillarObjective::Evaluate(const objectives::EvalInput& in) const {
  sim::InitThread();  // once per thread; later calls are free
  objectives::EvalResult r;
  double cycles, settle, timestep_ms, start_phase;
  const auto& defaults = params_.simulation;
  if (!objectives::ParamInRange(in, "cycles", 1, 50, defaults.measured_cycles, true, cycles, r.reason) ||
      !objectives::ParamInRange(in, "settle_cycles", 0, 20, defaults.settle_cycles, true, settle,
                                r.reason) ||
      !objectives::ParamInRange(in, "timestep_ms", 0.05, 2, defaults.timestep_s * 1e3, false,
                                timestep_ms, r.reason) ||
      !objectives::ParamInRange(in, "start_phase", 0, 1, 0, false, start_phase, r.reason)) {
    return r;
  }
  for (const auto& [name, value] : in.params) {
    if (name != "cycles" && name != "settle_cycles" && name != "timestep_ms" &&
        name != "start_phase") {
      r.reason = "unknown param " + name;
      return r;
    }
  }
  auto gait = Gait::FromGenes(in.genes);
  if (!gait.ok()) {
    r.reason = std::string(gait.status().message());
    return r;
  }
  // Option "set": parameter overrides NAME=VALUE,... (a model corrected by the gap finder).
  CaterpillarParams params = params_;
  if (auto it = in.options.find("set"); it != in.options.end()) {
    auto overrides = objectives::ParseOverrides(it->second);
    if (!overrides.ok()) {
      r.reason = "option set: " + std::string(overrides.status().message());
      return r;
    }
    for (const auto& [name, v] : *overrides) {
      if (auto s = SetParam(params, name, v); !s.ok()) {
        r.reason = "option set: " + std::string(s.message());
        return r;
      }
    }
  }
  EvalOptions options;
  options.measured_cycles = static_cast<int>(cycles);
  options.settle_cycles = static_cast<int>(settle);
  options.start_phase = start_phase;
  // An explicit timestep_ms wins; otherwise the (possibly overridden) parameter file's.
  options.timestep_s = in.params.count("timestep_ms") ? timestep_ms * 1e-3 : 0.0;
  const GaitEvaluation e = EvaluateGait(params, *gait, options);
  r.metrics["simulated_s"] = e.simulated_s;
  if (!e.valid) {
    r.reason = e.reason;
    return r;
  }
  r.valid = true;
  r.fitness = e.distance_per_cycle_m;
  r.metrics["distance_per_cycle"] = e.distance_per_cycle_m;
  r.metrics["max_body_pitch"] = e.max_body_pitch_rad;
  r.metrics["max_stroke"] = e.max_stroke_m;
  r.metrics["actuator_energy"] = e.actuator_energy_j;
  r.metrics["airborne_fraction"] = e.airborne_fraction;
  return r;
}

void RegisterCaterpillar(objectives::ObjectiveRegistry& registry) {
  registry.Register(kCaterpillarObjectiveName,
                    std::make_shared<CaterpillarObjective>(DefaultCaterpillarParams()));
}

}  // namespace gaitforge::caterpillar
