#include "workers/models/generic/generic_gait.h"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "robots/controllers.h"

namespace gaitforge::generic {

absl::StatusOr<std::vector<double>> Commands(const robots::RobotDescriptor& d,
                                             const std::vector<double>& genes, double t) {
  const robots::Controller& c = d.controller;
  if (genes.size() != c.genes.size())
    return absl::InvalidArgumentError(absl::StrCat(d.name, " takes ", c.genes.size(),
                                                   " genes, got ", genes.size()));
  if (c.kind != "sine")
    return absl::InvalidArgumentError(absl::StrCat(
        "the generic model drives servos with controller kind sine, not ", c.kind));
  std::vector<double> out(d.actuators.size(), 0.0);
  const double f = genes[0];
  for (size_t k = 0; k < c.actuators.size(); ++k) {
    const double amp = genes[1 + 3 * k], off = genes[2 + 3 * k], phase = genes[3 + 3 * k];
    for (size_t i = 0; i < d.actuators.size(); ++i) {
      if (d.actuators[i].name == c.actuators[k])
        out[i] = off + amp * std::sin(2 * M_PI * (f * t + phase));
    }
  }
  return out;
}

GaitResult EvaluateGait(const robots::RobotDescriptor& d, const ParamValues& v,
                        const std::vector<double>& genes, const GaitOptions& o) {
  GaitResult r;
  const robots::ControllerKind* kind = robots::FindControllerKind(d.controller.kind);
  if (auto first = Commands(d, genes, 0); !first.ok()) {
    r.reason = std::string(first.status().message());
    return r;
  }
  const double period = kind->period_s(genes);
  const int settle = o.settle_cycles >= 0 ? o.settle_cycles : static_cast<int>(v("simulation.settle_cycles"));
  const int measured =
      o.measured_cycles >= 0 ? o.measured_cycles : static_cast<int>(v("simulation.measured_cycles"));
  auto world = GenericWorld::Build(d, v, o.timestep_s);
  if (!world.ok()) {
    r.reason = std::string(world.status().message());
    return r;
  }
  GenericWorld& w = **world;
  const auto steps = [&](int cycles) {
    return static_cast<int64_t>(std::llround(cycles * period / w.timestep()));
  };
  double start_x = 0;
  const int64_t settle_steps = steps(settle), total = settle_steps + steps(measured);
  for (int64_t i = 0; i < total; ++i) {
    if (i == settle_steps) start_x = w.CentreOfMass()[0];
    const sim::SimOutcome out = w.Step(*Commands(d, genes, w.time()));
    if (!out.ok) {
      r.reason = out.reason;
      r.simulated_s = w.time();
      return r;
    }
  }
  if (settle_steps == total) start_x = w.CentreOfMass()[0];
  r.valid = true;
  r.simulated_s = w.time();
  r.distance_per_cycle_m = (w.CentreOfMass()[0] - start_x) / measured;
  return r;
}

}  // namespace gaitforge::generic
