#include "services/core/objective_catalog.h"

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "robots/registry.h"

namespace gaitforge::core {

std::vector<GeneRange> GeneSpaceOf(const robots::RobotDescriptor& robot) {
  std::vector<GeneRange> space;
  for (const auto& g : robot.controller.genes) space.push_back({g.name, g.lo, g.hi, g.circular});
  return space;
}

namespace {

// The analytic objectives' default space: 13 genes x1..x13 in [0, 1] (the size of the
// gait spaces they were first benchmarked beside; a function maps each gene relative to its
// range, so only the number matters).
std::vector<GeneRange> AnalyticSpace() {
  std::vector<GeneRange> space;
  for (int i = 1; i <= 13; ++i) space.push_back({absl::StrCat("x", i), 0, 1});
  return space;
}

// A catalog parameter whose range and default are the robot's parameter `name`, times
// `factor` (1000 for a timestep in ms).
ParamInfo FromRobot(const char* robot, const char* param, const char* name, std::string meaning,
                    double factor = 1) {
  const robots::Parameter& p = *robots::Robot(robot).FindParameter(name);
  return {param, p.lo * factor, p.hi * factor, p.value * factor, std::move(meaning), p.integer};
}

std::vector<ParamInfo> AnalyticParams() {
  return {
      {"work_us", 0, 1e6, 0,
       "busy compute added to each evaluation, in microseconds (emulates a simulator's cost)"},
      {"shift", -1, 1, 0.2,
       "offset of the optimum from the centre of the space, in units of half the range"},
  };
}

// The params of every calibration's comparison (workers/objectives/recording_comparison.h).
std::vector<ParamInfo> ComparisonParams(ParamInfo settle_cycles, ParamInfo timestep_ms) {
  return {std::move(settle_cycles),
          {"max_shift_samples", 0, 1000, 10,
           "largest time shift searched, in samples (shape/stats: period bins, at most half a "
           "period)",
           true},
          std::move(timestep_ms),
          {"z_weight", 0, 100, 1,
           "error = stats: weight of the relative z-shape error against the distance error"},
          {"min_distance_m", 1e-6, 1, 1e-3,
           "error = stats: floor of |real distance per cycle| in the relative distance error "
           "(m)"},
          {"window_s", 0, 1e4, 0,
           "error = acceleration: compare the first window_s seconds of each recording (paper "
           "004: 0.2); 0: all of it"}};
}

ParamInfo StartPhase() {
  return {"start_phase", 0, 1, 0,
          "the gait's phase at t = 0, in cycles: the controller starts this far into its cycle"};
}

std::vector<std::pair<std::string, std::vector<std::string>>> ComparisonOptions() {
  return {{"error", {"shape", "pointwise", "stats", "acceleration"}},
          {"metric", {"rmse", "mae"}},
          {"channels", {}},
          {"weights", {}}};
}

// An analytic test function's entry: genes only, no recordings, no robot.
ObjectiveInfo AnalyticEntry(std::string name, std::string summary, bool with_params) {
  ObjectiveInfo o;
  o.name = std::move(name);
  o.summary = std::move(summary);
  if (with_params) o.params = AnalyticParams();
  o.default_space = AnalyticSpace();
  return o;
}

std::vector<ObjectiveInfo> AnalyticCatalog() {
  return {
      AnalyticEntry("analytic.sphere",
                    "fitness = -sum z_i^2 over genes mapped to z in [-5, 5)",
                    true),
      AnalyticEntry("analytic.ellipsoid",
                    "fitness = -sum 1e6^(i/(n-1)) z_i^2 (conditioning 1e6)",
                    true),
      AnalyticEntry("analytic.rosenbrock",
                    "fitness = -sum 100 (z_{i+1} - z_i^2)^2 + (1 - z_i)^2",
                    true),
      AnalyticEntry("analytic.rastrigin",
                    "fitness = -(10 n + sum z_i^2 - 10 cos(2 pi z_i))",
                    true),
      AnalyticEntry("analytic.zdt1",
                    "two objectives for nsga2: metrics f1 = u_0 and f2 = g (1 - sqrt(f1 / g)), "
                    "g = 1 + 9 mean(u_1..), genes mapped to u in [0, 1); fitness = -(f1 + f2)",
                    false),
  };
}

std::vector<ObjectiveInfo> RobotAgnosticCatalog() {
  return {
      {"robot.distance",
       "forward travel (m) per gait cycle of any robot whose descriptor has model: generic "
       "(objective.robot; docs/robots.md), measured after settle_cycles from rest, or in "
       "duration_s from rest; genes: the robot's controller's, then any of its parameters "
       "(a body searched with its gait); metrics max_tilt_rad, torque_limited_fraction, "
       "servo_energy_j and cost_of_transport for constraints (with the robot's electrical "
       "section also electrical_energy_j, electrical_power_w and "
       "electrical_cost_of_transport); option fitness: cost_of_transport or "
       "electrical_cost_of_transport makes the fitness minus that cost of transport",
       {{"cycles", 1, 50, 2,
         "measured gait cycles (default: the robot's simulation.measured_cycles)", true},
        {"duration_s", 0, 600, 0,
         "> 0: fitness is the forward travel (m) of the centre of mass in this time from rest, "
         "start-up included, instead of travel per cycle; 0: per cycle (default: the robot's "
         "simulation.duration_s when it has one, else 0)"},
        {"settle_cycles", 0, 20, 1,
         "gait cycles from rest before measuring (default: the robot's simulation.settle_cycles)",
         true},
        {"timestep_ms", 0.05, 2, 1,
         "ODE timestep in ms (default: the robot's simulation.timestep_s)"},
        StartPhase()},
       {},
       0,
       // set: parameter overrides NAME=VALUE,... of the robot's descriptor; fitness: travel
       // (the default), cost_of_transport (fitness = -servo work / (weight x travel)) or
       // electrical_cost_of_transport (-battery energy / (weight x travel)).
       {{"set", {}}, {"fitness", {"travel", "cost_of_transport", "electrical_cost_of_transport"}}},
       false,
       "",
       false,
       {},
       true,
       "",
       true},
      {"robot.calibration",
       "calibration of any robot whose descriptor has model: generic (objective.robot) against "
       "recordings of it: fitness = -(mean error over the recordings, weighted by the weights "
       "option when given) between recorded and simulated channels (m, rad; relative for "
       "error = stats); genes are the robot's calibratable parameters and scales, the effects "
       "the generic builder attaches (effect.*, docs/effects.md), and nuisance.time_offset_s",
       ComparisonParams({"settle_cycles", 0, 20, 1,
                         "gait cycles from rest left out of the comparison (default: the "
                         "robot's simulation.settle_cycles)",
                         true},
                        {"timestep_ms", 0.05, 2, 1,
                         "ODE timestep in ms (default: the robot's simulation.timestep_s)"}),
       {},
       0,
       ComparisonOptions(),
       true,
       "",
       true,
       {"nuisance.time_offset_s"},
       true,
       "",
       false},
      {"robot.tracking",
       "paper 004's tracking by any generic robot with a tracking section (objective.robot): "
       "it follows each recording (a path of its tracked marker) from rest with its PID; "
       "fitness = -(mean over the paths of ISTE, or the max or RMS error: option fitness); "
       "genes are its calibratable parameters named in bounds (the PID's gains tracking.kp, "
       "ki, kd), set on the robot that tracks (the descriptor with option set); option "
       "feedforward model adds the feed-forward learned on the descriptor with option "
       "model_set; metrics max_error_m, rms_error_m, iste, model_rms_error_m",
       {{"ff_iterations", 1, 200, 20, "model runs that learn the feed-forward", true}},
       {},
       0,
       {{"feedforward", {"none", "model"}},
        {"fitness", {"iste", "max", "rms"}},
        {"set", {}},
        {"model_set", {}}},
       true,
       "",
       true,
       {},
       true,
       "",
       false},
  };
}


// A built-in robot's own name for robot.distance bound to it (its descriptor's
// `objectives.distance`): its gait space, its simulation defaults.
ObjectiveInfo OwnDistance(const robots::RobotDescriptor& r) {
  const char* robot = r.name.c_str();
  return {r.distance_objective,
          absl::StrCat("robot.distance of the built-in robot ", r.name, " (robots/", r.name,
                       "/robot.yaml): forward travel (m) per gait cycle, measured after "
                       "settle_cycles from rest"),
          {FromRobot(robot, "cycles", "simulation.measured_cycles",
                     "measured gait cycles; fitness is the mean travel per cycle (m)"),
           FromRobot(robot, "settle_cycles", "simulation.settle_cycles",
                     "gait cycles from rest before measuring"),
           FromRobot(robot, "timestep_ms", "simulation.timestep_s",
                     "ODE timestep in ms (default: the robot's simulation.timestep_s)", 1000),
           StartPhase()},
          GeneSpaceOf(r),
          static_cast<int>(r.controller.genes.size()),
          // set: parameter overrides NAME=VALUE,... (e.g. the gap finder's corrected model).
          {{"set", {}}},
          false,
          "",
          false,
          {},
          false,
          r.name,
          true};
}

// A built-in robot's own name for robot.calibration bound to it (`objectives.calibration`).
ObjectiveInfo OwnCalibration(const robots::RobotDescriptor& r) {
  const char* robot = r.name.c_str();
  return {r.calibration_objective,
          absl::StrCat("robot.calibration of the built-in robot ", r.name,
                       " against recordings: fitness = -(mean error over the recordings, "
                       "weighted by the weights option when given) between recorded and "
                       "simulated channels (m; relative for error = stats); genes are its "
                       "parameters named in bounds, plus nuisance.time_offset_s"),
          ComparisonParams(
              FromRobot(robot, "settle_cycles", "simulation.settle_cycles",
                        "gait cycles from rest (simulated time) left out of the comparison"),
              FromRobot(robot, "timestep_ms", "simulation.timestep_s",
                        "ODE timestep in ms (default: the robot's simulation.timestep_s)", 1000)),
          {},
          0,
          ComparisonOptions(),
          true,
          r.name,
          true,
          // recording time t corresponds to simulated time t + offset (s)
          {"nuisance.time_offset_s"},
          false,
          "",
          false};
}

// The analytic family, then the built-in robots' own objective names, then the
// robot-agnostic objectives.
std::vector<ObjectiveInfo> BuildCatalog() {
  std::vector<ObjectiveInfo> catalog = AnalyticCatalog();
  for (const std::string& name : robots::RobotNames()) {
    const robots::RobotDescriptor& r = robots::Robot(name);
    if (!r.distance_objective.empty()) catalog.push_back(OwnDistance(r));
    if (!r.calibration_objective.empty()) catalog.push_back(OwnCalibration(r));
  }
  for (ObjectiveInfo& o : RobotAgnosticCatalog()) catalog.push_back(std::move(o));
  return catalog;
}

}  // namespace

const std::vector<ObjectiveInfo>& ObjectiveCatalog() {
  static const std::vector<ObjectiveInfo> catalog = BuildCatalog();
  return catalog;
}


absl::StatusOr<std::shared_ptr<const robots::RobotDescriptor>> RobotOfObjective(
    const ObjectiveInfo& info, const std::string& robot, const std::string& descriptor) {
  if (info.uses_robot) return robots::ResolveRobot(robot, descriptor);
  const std::string& bound = info.gait_robot.empty() ? info.calibrates : info.gait_robot;
  if (bound.empty())
    return absl::InvalidArgumentError(absl::StrCat(info.name, " simulates no robot"));
  return robots::ResolveRobot(bound, "");
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
