// Running a generic robot from rest under a command source (generic_run.h).
#include "workers/models/generic/generic_run.h"

#include "absl/strings/str_cat.h"

namespace gaitforge::generic {

bool RunWorld(const robots::RobotDescriptor& d, const ParamValues& v, double timestep_s,
              const WorldBuilder& engine, const std::function<int64_t(const RobotWorld&)>& steps,
              const std::function<void(const RobotWorld&, int64_t)>& each,
              const std::function<Source(const RobotWorld&)>& source, std::string* reason,
              double* simulated_s) {
  absl::StatusOr<std::unique_ptr<RobotWorld>> world;
  if (engine) {
    world = engine(d, v, timestep_s);
  } else if (auto ode = GenericWorld::Build(d, v, timestep_s); ode.ok()) {
    world = std::unique_ptr<RobotWorld>(std::move(*ode));
  } else {
    world = ode.status();
  }
  if (!world.ok()) {
    *reason = std::string(world.status().message());
    return false;
  }
  RobotWorld& w = **world;
  const int64_t total = steps(w);
  const Source commands_of = source(w);
  std::vector<double> commands;
  // A robot whose descriptor says when its first body has fallen (simulation.fall_tilt_rad):
  // past that tilt the run is invalid with the reason, never travel (issue 28).
  const double fall =
      d.FindParameter("simulation.fall_tilt_rad") ? v("simulation.fall_tilt_rad") : 0;
  for (int64_t i = 0; i < total; ++i) {
    each(w, i);
    commands_of(i, commands);
    sim::SimOutcome out = w.Step(commands);
    if (out.ok && fall > 0 && w.max_tilt() > fall)
      out = sim::SimOutcome::Failed(
          absl::StrCat("fell: ", d.bodies.front().name, " tilted ", w.max_tilt(),
                       " rad (> simulation.fall_tilt_rad = ", fall, ") at t = ", w.time(), " s"));
    if (!out.ok) {
      *reason = out.reason;
      *simulated_s = w.time();
      return false;
    }
  }
  each(w, total);
  *simulated_s = w.time();
  return true;
}

}  // namespace gaitforge::generic
