#include "services/core/objective_catalog.h"

#include "absl/strings/str_join.h"

namespace gaitforge::core {

const std::vector<GeneRange>& CaterpillarGaitSpace() {
  static const std::vector<GeneRange> space = {
      {"a_T1", 0, 1}, {"a_T2", 0, 1}, {"a_T3", 0, 1}, {"a_B1", 0, 1}, {"a_B2", 0, 1},
      {"a_B3", 0, 1}, {"d_T1", 0, 1}, {"d_T2", 0, 1}, {"d_T3", 0, 1}, {"d_B1", 0, 1},
      {"d_B2", 0, 1}, {"d_B3", 0, 1}, {"T", 0.2, 2.0},
  };
  return space;
}

namespace {

std::vector<ParamInfo> AnalyticParams() {
  return {
      {"work_us", 0, 1e6, 0,
       "busy compute added to each evaluation, in microseconds (emulates a simulator's cost)"},
      {"shift", -1, 1, 0.2,
       "offset of the optimum from the centre of the space, in units of half the range"},
  };
}

}  // namespace

const std::vector<ObjectiveInfo>& ObjectiveCatalog() {
  static const std::vector<ObjectiveInfo> catalog = {
      {"analytic.sphere",
       "fitness = -sum z_i^2 over genes mapped to z in [-5, 5)",
       AnalyticParams(), CaterpillarGaitSpace(), 0, {}, false},
      {"analytic.ellipsoid",
       "fitness = -sum 1e6^(i/(n-1)) z_i^2 (conditioning 1e6)",
       AnalyticParams(), CaterpillarGaitSpace(), 0, {}, false},
      {"analytic.rosenbrock",
       "fitness = -sum 100 (z_{i+1} - z_i^2)^2 + (1 - z_i)^2",
       AnalyticParams(), CaterpillarGaitSpace(), 0, {}, false},
      {"analytic.rastrigin",
       "fitness = -(10 n + sum z_i^2 - 10 cos(2 pi z_i))",
       AnalyticParams(), CaterpillarGaitSpace(), 0, {}, false},
      {"caterpillar.distance",
       "forward travel (m) per gait cycle of the lumped ODE caterpillar "
       "(../shared/robots/caterpillar.md), measured after settle_cycles from rest",
       {{"cycles", 1, 50, 1, "measured gait cycles; fitness is the mean travel per cycle (m)",
         true},
        {"settle_cycles", 0, 20, 2, "gait cycles from rest before measuring", true},
        {"timestep_ms", 0.05, 2, 1, "ODE timestep in ms (default from caterpillar.yaml)"}},
       CaterpillarGaitSpace(), 13,
       // set: model parameter overrides NAME=VALUE,... (e.g. the gap finder's corrected model).
       {{"set", {}}}},
      {"caterpillar.calibration",
       "calibration of the lumped ODE caterpillar against recordings (paper 003): fitness = "
       "-(mean error over the recordings, weighted by the weights option when given) between "
       "recorded and simulated markers (m; relative for error = stats); genes are model "
       "parameters named in bounds, plus nuisance.time_offset_s",
       {{"settle_cycles", 0, 20, 2,
         "gait cycles from rest (simulated time) left out of the comparison", true},
        {"max_shift_samples", 0, 1000, 10,
         "largest time shift searched, in samples (shape/stats: period bins, at most half a "
         "period)",
         true},
        {"timestep_ms", 0.05, 2, 1, "ODE timestep in ms (default from caterpillar.yaml)"},
        {"z_weight", 0, 100, 1,
         "error = stats: weight of the relative z-shape error against the distance error"},
        {"min_distance_m", 1e-6, 1, 1e-3,
         "error = stats: floor of |real distance per cycle| in the relative distance error (m)"}},
       {},
       0,
       {{"error", {"shape", "pointwise", "stats"}},
        {"metric", {"rmse", "mae"}},
        {"channels", {}},
        {"weights", {}}},
       true},
  };
  return catalog;
}

const ObjectiveInfo* FindObjective(std::string_view name) {
  for (const auto& o : ObjectiveCatalog()) {
    if (o.name == name) return &o;
  }
  return nullptr;
}

std::string ObjectiveNames() {
  std::vector<std::string> names;
  for (const auto& o : ObjectiveCatalog()) names.push_back(o.name);
  return absl::StrJoin(names, ", ");
}

}  // namespace gaitforge::core
