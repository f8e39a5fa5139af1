#include "workers/models/generic/generic_objective.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include "robots/registry.h"
#include "workers/models/generic/generic_calibration.h"
#include "workers/models/generic/generic_tracking_objective.h"
#include "workers/models/generic/generic_gait.h"
#include "workers/objectives/overrides.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::generic {
namespace {

// Applies option set's NAME=VALUE,... in order; the error says which item and why.
absl::Status ApplySet(const std::string& text, ParamValues& values) {
  auto overrides = objectives::ParseOverrides(text);
  if (!overrides.ok())
    return absl::InvalidArgumentError("option set: " + std::string(overrides.status().message()));
  for (const auto& [name, v] : *overrides) {
    if (auto s = values.Set(name, v); !s.ok())
      return absl::InvalidArgumentError("option set: " + std::string(s.message()));
  }
  return absl::OkStatus();
}

// The params the coordinator validated against the catalog, checked again for what would
// make the evaluation meaningless (a worker may meet a job no coordinator checked): the
// names robot.distance knows, whole cycles, a positive step, a phase within a cycle.
std::string CheckParams(const objectives::EvalInput& in) {
  static const char* kKnown[] = {"cycles", "settle_cycles", "timestep_ms", "start_phase",
                                 "duration_s"};
  for (const auto& [name, value] : in.params)
    if (std::find(std::begin(kKnown), std::end(kKnown), name) == std::end(kKnown))
      return "unknown param " + name;
  double v;
  std::string error;
  if (!objectives::ParamInRange(in, "cycles", 1, 1e6, 1, true, v, error) ||
      !objectives::ParamInRange(in, "settle_cycles", 0, 1e6, 0, true, v, error) ||
      !objectives::ParamInRange(in, "timestep_ms", 1e-6, 1e3, 1, false, v, error) ||
      !objectives::ParamInRange(in, "start_phase", 0, 1, 0, false, v, error) ||
      !objectives::ParamInRange(in, "duration_s", 0, 1e6, 0, false, v, error))
    return error;
  return "";
}

}  // namespace

objectives::EvalResult RobotDistanceObjective::Evaluate(const objectives::EvalInput& in) const {
  sim::InitThread();
  objectives::EvalResult r;
  auto robot = robots::ResolveRobot(in.robot, in.robot_descriptor);
  if (!robot.ok()) {
    r.reason = "robot: " + std::string(robot.status().message());
    return r;
  }
  if (r.reason = CheckParams(in); !r.reason.empty()) return r;
  ParamValues values(**robot);
  if (auto it = in.options.find("set"); it != in.options.end()) {
    if (auto s = ApplySet(it->second, values); !s.ok()) {
      r.reason = std::string(s.message());
      return r;
    }
  }
  // Genes past the controller's are the robot's parameters (a body searched with its gait).
  const size_t gait = std::min(in.genes.size(), (*robot)->controller.genes.size());
  for (size_t i = gait; i < in.genes.size(); ++i) {
    const std::string name = i < in.gene_names.size() ? in.gene_names[i] : "";
    if (auto s = values.Set(name, in.genes[i]); !s.ok()) {
      r.reason = "gene " + name + ": " + std::string(s.message());
      return r;
    }
  }
  const std::vector<double> gait_genes(in.genes.begin(), in.genes.begin() + gait);
  GaitOptions o;
  if (auto it = in.params.find("cycles"); it != in.params.end()) o.measured_cycles = static_cast<int>(it->second);
  if (auto it = in.params.find("settle_cycles"); it != in.params.end()) o.settle_cycles = static_cast<int>(it->second);
  if (auto it = in.params.find("timestep_ms"); it != in.params.end()) o.timestep_s = it->second * 1e-3;
  if (auto it = in.params.find("start_phase"); it != in.params.end()) o.start_phase = it->second;
  if (auto it = in.params.find("duration_s"); it != in.params.end())
    o.duration_s = it->second;
  else if ((*robot)->FindParameter("simulation.duration_s"))
    o.duration_s = values("simulation.duration_s");
  const GaitResult g = EvaluateGait(**robot, values, gait_genes, o);
  r.metrics["simulated_s"] = g.simulated_s;
  if (!g.valid) {
    r.reason = g.reason;
    return r;
  }
  r.metrics["max_tilt_rad"] = g.max_tilt_rad;
  r.metrics["torque_limited_fraction"] = g.torque_limited_fraction;
  r.metrics["servo_energy_j"] = g.servo_energy_j;
  r.metrics["max_body_pitch"] = g.max_body_pitch_rad;
  if (g.airborne_fraction >= 0) r.metrics["airborne_fraction"] = g.airborne_fraction;
  const bool pistons = std::any_of((*robot)->actuators.begin(), (*robot)->actuators.end(),
                                   [](const robots::Actuator& a) { return a.type == "piston"; });
  if (pistons) {
    r.metrics["max_stroke"] = g.max_stroke_m;
    r.metrics["actuator_energy"] = g.piston_work_j;
  }
  // Cost of transport: work per weight and distance (dimensionless; paper 002's measure),
  // mechanical (the servos' positive work) and electrical (the battery's energy).
  const double work = g.servo_energy_j + g.piston_work_j;
  const double cot = g.travel_m > 0 ? work / (g.weight_n * g.travel_m) : NAN;
  if (g.travel_m > 0) r.metrics["cost_of_transport"] = cot;
  const double electrical_cot =
      g.electrical && g.travel_m > 0 ? g.electrical_energy_j / (g.weight_n * g.travel_m) : NAN;
  if (g.electrical) {
    r.metrics["electrical_energy_j"] = g.electrical_energy_j;
    if (g.measured_s > 0) r.metrics["electrical_power_w"] = g.electrical_energy_j / g.measured_s;
    if (g.travel_m > 0) r.metrics["electrical_cost_of_transport"] = electrical_cot;
  }
  if (g.measured_s > 0) r.metrics["speed_m_s"] = g.travel_m / g.measured_s;
  if (o.duration_s > 0) {
    r.fitness = g.travel_m;
    r.metrics["travel"] = g.travel_m;
  } else {
    r.fitness = g.distance_per_cycle_m;
    r.metrics["distance_per_cycle"] = g.distance_per_cycle_m;
  }
  if (auto it = in.options.find("fitness"); it != in.options.end() && it->second != "travel") {
    if (it->second == "electrical_cost_of_transport" && !g.electrical) {
      r.reason =
          "electrical cost of transport: the robot has no electrical section (docs/robots.md)";
      return r;
    }
    if (!(g.travel_m > 0)) {
      r.reason = "cost of transport: the robot did not move forward";
      return r;
    }
    r.fitness = it->second == "cost_of_transport" ? -cot : -electrical_cot;
  }
  r.valid = true;
  return r;
}

namespace {

class RobotObjective : public objectives::Objective {
 public:
  RobotObjective(std::shared_ptr<const objectives::Objective> objective, std::string robot)
      : objective_(std::move(objective)), robot_(std::move(robot)) {}
  objectives::EvalResult Evaluate(const objectives::EvalInput& in) const override {
    objectives::EvalInput mine = in;
    mine.robot = robot_;
    mine.robot_descriptor.clear();
    return objective_->Evaluate(mine);
  }

 private:
  std::shared_ptr<const objectives::Objective> objective_;
  std::string robot_;
};

}  // namespace

void RegisterRobotObjective(objectives::ObjectiveRegistry& registry, const std::string& name,
                            const std::string& objective, const std::string& robot) {
  std::shared_ptr<const objectives::Objective> inner;
  if (objective == kRobotDistanceName) inner = std::make_shared<RobotDistanceObjective>();
  if (objective == kRobotCalibrationName) inner = std::make_shared<RobotCalibrationObjective>();
  if (!inner) throw std::invalid_argument("RegisterRobotObjective: no objective " + objective);
  registry.Register(name, std::make_shared<RobotObjective>(std::move(inner), robot));
}

void RegisterGeneric(objectives::ObjectiveRegistry& registry) {
  registry.Register(kRobotDistanceName, std::make_shared<RobotDistanceObjective>());
  registry.Register(kRobotCalibrationName, std::make_shared<RobotCalibrationObjective>());
  registry.Register(kRobotTrackingName, std::make_shared<RobotTrackingObjective>());
}

}  // namespace gaitforge::generic
