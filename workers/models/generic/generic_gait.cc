#include "workers/models/generic/generic_gait.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>

#include "absl/strings/str_cat.h"
#include "robots/controllers.h"
#include "workers/models/generic/generic_run.h"
#include "workers/models/generic/power_meter.h"

namespace gaitforge::generic {

absl::StatusOr<std::vector<double>> Commands(const robots::RobotDescriptor& d,
                                             const std::vector<double>& genes, double t) {
  const robots::Controller& c = d.controller;
  if (genes.size() != c.genes.size())
    return absl::InvalidArgumentError(absl::StrCat(d.name, " takes ", c.genes.size(),
                                                   " genes, got ", genes.size()));
  for (size_t i = 0; i < genes.size(); ++i)
    if (!std::isfinite(genes[i]))
      return absl::InvalidArgumentError(absl::StrCat("gene ", i, " (", c.genes[i].name, ") is not finite"));
  const robots::ControllerKind& kind = *robots::FindControllerKind(c.kind);
  const double period = kind.period_s(genes);
  if (!(period > 0) || period < kind.min_period_s || period > kind.max_period_s)
    return absl::InvalidArgumentError(
        kind.max_period_s < 1e300
            ? absl::StrCat("gait period T = ", period, " s is outside [", kind.min_period_s, ", ",
                           kind.max_period_s, "] s")
            : absl::StrCat("the genes give a gait period of ", period, " s"));
  if (kind.check)
    if (std::string why = kind.check(c, genes); !why.empty()) return absl::InvalidArgumentError(why);
  // Servos take set-point angles; pistons the fraction of their force (on/off: 1 or 0);
  // tendons a force, which no gait kind gives yet. Holding (all 0) suits every type.
  for (const std::string& name : kind.name == "hold" ? std::vector<std::string>{} : c.actuators)
    for (const robots::Actuator& a : d.actuators)
      if (a.name == name && (a.type == "tendon" || (a.type == "servo") != kind.set_points))
        return absl::InvalidArgumentError(absl::StrCat(
            "controller kind ", c.kind, kind.set_points ? " gives set-point angles" : " switches on and off",
            ", which ", a.type, " ", a.name, " cannot take"));
  return DescriptorOrder(d)(robots::ControllerRun(c, genes).At(t));
}

DescriptorOrder::DescriptorOrder(const robots::RobotDescriptor& d) : actuators_(d.actuators.size()) {
  for (const std::string& name : d.controller.actuators)
    for (size_t i = 0; i < d.actuators.size(); ++i)
      if (d.actuators[i].name == name) slot_.push_back(i);
}

void DescriptorOrder::Place(const std::vector<double>& command, std::vector<double>& out) const {
  const bool torques = !slot_.empty() && command.size() == 2 * slot_.size();
  out.assign(torques ? 2 * actuators_ : actuators_, 0.0);
  for (size_t k = 0; k < slot_.size() && k < command.size(); ++k) out[slot_[k]] = command[k];
  if (torques)
    for (size_t k = 0; k < slot_.size(); ++k) out[actuators_ + slot_[k]] = command[slot_.size() + k];
}

std::vector<double> DescriptorOrder::operator()(const std::vector<double>& command) const {
  std::vector<double> out;
  Place(command, out);
  return out;
}

namespace {

// The commands of step n (time n h) under a command delay d (effect.actuator_delay_s). A
// set-point kind is continuous in time: its command of time max(0, t - d). An on/off kind
// is held over each step, so the delayed command over the step is the one of step n - D - 1
// for the first `frac` of it and of step n - D for the rest (d = (D + frac) h; OFF before
// the start): continuous in d, a fraction of a step delaying that share of its push.
class DelayedCommands {
 public:
  DelayedCommands(const robots::ControllerKind& kind, double delay_s, double h)
      : on_off_(!kind.set_points && delay_s > 0), delay_(delay_s), h_(h) {
    if (!on_off_) return;
    double steps = delay_s / h;
    if (std::fabs(steps - std::round(steps)) < 1e-9) steps = std::round(steps);
    whole_ = static_cast<int64_t>(std::floor(steps));
    frac_ = steps - static_cast<double>(whole_);
  }
  std::vector<double> At(robots::ControllerRun& run, int64_t n, double offset, size_t count,
                         const robots::BodyState* base = nullptr) const {
    if (!on_off_) return run.At(std::max(0.0, static_cast<double>(n) * h_ - delay_) + offset, base);
    auto at_step = [&](int64_t k) {
      return k >= 0 ? run.At(static_cast<double>(k) * h_ + offset) : std::vector<double>(count, 0.0);
    };
    const std::vector<double> older = frac_ != 0 ? at_step(n - whole_ - 1) : std::vector<double>();
    std::vector<double> out = at_step(n - whole_);
    if (frac_ != 0)
      for (size_t j = 0; j < out.size(); ++j) out[j] = frac_ * older[j] + (1 - frac_) * out[j];
    return out;
  }

 private:
  bool on_off_;
  double delay_, h_;
  int64_t whole_ = 0;
  double frac_ = 0;
};

// Runs the gait from rest (RunWorld). The controller runs `time_offset_s` ahead of the
// world (a start phase).
bool Run(const robots::RobotDescriptor& d, const ParamValues& v, const std::vector<double>& genes,
         double timestep_s, double time_offset_s, const WorldBuilder& engine,
         const std::function<int64_t(const RobotWorld&)>& steps,
         const std::function<void(const RobotWorld&, int64_t)>& each, std::string* reason,
         double* simulated_s) {
  if (auto first = Commands(d, genes, 0); !first.ok()) {
    *reason = std::string(first.status().message());
    return false;
  }
  robots::ControllerRun controller(d.controller, genes);
  const DescriptorOrder order(d);
  const auto source = [&](const RobotWorld& w) -> Source {
    auto delayed = std::make_shared<DelayedCommands>(
        *robots::FindControllerKind(d.controller.kind), v.Effect("effect.actuator_delay_s"),
        w.timestep());
    // A feedback controller reads the base's state now (a delay shifts its schedule only).
    return [&, delayed](int64_t i, std::vector<double>& out) {
      robots::BodyState base;
      if (controller.feedback()) base = w.StateOf(0);
      order.Place(delayed->At(controller, i, time_offset_s, d.controller.actuators.size(),
                              controller.feedback() ? &base : nullptr),
                  out);
    };
  };
  return RunWorld(d, v, timestep_s, engine, steps, each, source, reason, simulated_s);
}

}  // namespace

calibration::SimRun SimulateChannels(const robots::RobotDescriptor& d, const ParamValues& v,
                                     const std::vector<double>& genes, int cycles, double rate_hz,
                                     double timestep_s, const WorldBuilder& engine,
                                     int settle_cycles) {
  calibration::SimRun run;
  const robots::ControllerKind* kind = robots::FindControllerKind(d.controller.kind);
  const double period = genes.size() == d.controller.genes.size() ? kind->period_s(genes) : 1;
  calibration::Trajectory& tr = run.trajectory;
  tr.channels = d.Channels();
  tr.columns.resize(tr.channels.size());
  int64_t every = 1, from = 0;
  const auto steps = [&](const RobotWorld& w) {
    every = std::max<int64_t>(1, std::llround(1.0 / (rate_hz * w.timestep())));
    from = std::llround(settle_cycles * period / w.timestep());
    return static_cast<int64_t>(std::llround((settle_cycles + cycles) * period / w.timestep()));
  };
  const auto sample = [&](const RobotWorld& w, int64_t i) {
    if (i < from || (i - from) % every != 0) return;
    tr.t.push_back(w.time());
    for (size_t c = 0; c < tr.channels.size(); ++c) tr.columns[c].push_back(*w.Channel(tr.channels[c]));
  };
  run.valid = Run(d, v, genes, timestep_s, 0, engine, steps, sample, &run.reason, &run.simulated_s);
  return run;
}

GaitResult EvaluateGait(const robots::RobotDescriptor& d, const ParamValues& v,
                        const std::vector<double>& genes, const GaitOptions& o) {
  GaitResult r;
  const int settle = o.settle_cycles >= 0 ? o.settle_cycles : static_cast<int>(v("simulation.settle_cycles"));
  const int measured =
      o.measured_cycles >= 0 ? o.measured_cycles : static_cast<int>(v("simulation.measured_cycles"));
  const robots::ControllerKind* kind = robots::FindControllerKind(d.controller.kind);
  int64_t settle_steps = 0, total = 0, airborne = 0;
  double start_x = 0, end_x = 0, start_energy = 0;
  const int last_body = static_cast<int>(d.bodies.size()) - 1;
  bool contacts_known = true;
  auto made = PowerMeter::For(d, v);
  if (!made.ok()) {
    r.reason = std::string(made.status().message());
    return r;
  }
  const std::unique_ptr<PowerMeter> meter = std::move(*made);
  const auto steps = [&](const RobotWorld& w) {
    if (o.duration_s > 0) return total = std::llround(o.duration_s / w.timestep());
    const double period = kind->period_s(genes);
    // Both from integer arithmetic: the measured window starts and ends at exactly settle
    // and settle + measured periods, each up to one step.
    settle_steps = std::llround(settle * period / w.timestep());
    return total = std::llround((settle + measured) * period / w.timestep());
  };
  const auto each = [&](const RobotWorld& w, int64_t i) {
    if (i == settle_steps) {
      start_x = w.CentreOfMass()[0];
      start_energy = w.servo_energy();
    }
    if (i > settle_steps) {  // the state after a measured step
      if (meter) meter->Step(w.actuator_torques(), w.actuator_rates(), w.timestep());
      r.measured_s += w.timestep();
      airborne += w.ground_contacts() == 0;
      r.piston_work_j += w.last_piston_work();
      contacts_known = contacts_known && w.ground_contacts() >= 0;
      for (double e : w.piston_extensions()) r.max_stroke_m = std::max(r.max_stroke_m, e);
      const auto rear = w.BodyCentre(0), front = w.BodyCentre(last_body);
      r.max_body_pitch_rad =
          std::max(r.max_body_pitch_rad, std::fabs(std::atan2(front[2] - rear[2], front[0] - rear[0])));
    }
    r.max_tilt_rad = w.max_tilt();
    r.torque_limited_fraction = w.torque_limited_fraction();
    r.servo_energy_j = w.servo_energy() - start_energy;
    if (i == 0) r.weight_n = w.total_mass() * v("simulation.gravity_m_per_s2");
    if (i == total) end_x = w.CentreOfMass()[0];
  };
  const double offset =
      genes.size() == d.controller.genes.size() ? o.start_phase * kind->period_s(genes) : 0;
  if (!Run(d, v, genes, o.timestep_s, offset, o.engine, steps, each, &r.reason, &r.simulated_s))
    return r;
  r.valid = true;
  const int64_t measured_steps = std::max<int64_t>(1, total - settle_steps);
  r.airborne_fraction = contacts_known ? static_cast<double>(airborne) / static_cast<double>(measured_steps) : -1;
  r.travel_m = end_x - start_x;
  if (meter) {
    r.electrical = true;
    r.electrical_energy_j = meter->energy_j();
  }
  r.distance_per_cycle_m = r.travel_m / measured;
  return r;
}

}  // namespace gaitforge::generic
