#pragma once
// Controller kinds a descriptor may name (docs/robots.md, "controller"). A kind turns the
// descriptor's controller section into its gene space; the worker side that runs it is
// registered by the same name. Adding a kind is one entry in ControllerKinds().
#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "robots/descriptor.h"

namespace gaitforge::robots {

// A body's state as a feedback controller sees it (the robot's first body, its base): its
// centre, its rotation (row-major, body frame to world), its centre's velocity and its
// angular velocity (world frame).
struct BodyState {
  std::array<double, 3> position{};
  std::array<double, 9> rotation{1, 0, 0, 0, 1, 0, 0, 0, 1};
  std::array<double, 3> velocity{}, spin{};
};

struct ControllerKind {
  std::string name;
  std::string doc;
  // The ranges the descriptor must give (controller.<key>: [lo, hi]).
  std::vector<std::string> range_keys;
  // The gene space of a controller of this kind (its actuators and ranges already read).
  std::vector<Gene> (*genes)(const Controller&);
  // The gait period (s) of a genotype of this kind.
  double (*period_s)(const std::vector<double>& genes);
  // Each of the controller's actuators' command at time t >= 0 (s), in its `actuators`
  // order: phase_onoff 1 (ON) or 0 (OFF); sine the set-point angle (rad). The genes must
  // be a genotype of this kind (the gene space's count).
  std::vector<double> (*commands)(const Controller& c, const std::vector<double>& genes,
                                  double t);
  // True when the commands are set-point angles (servos), false for on/off.
  bool set_points = true;
  // The number of actuators the kind drives (0: any).
  int actuators = 0;
  // A kind with state (cpg: coupled oscillators) gives its state at t = 0, one step of it,
  // and the commands of a state; `commands` then integrates from 0 (ControllerRun does
  // it once per run).
  std::vector<double> (*initial_state)(const Controller& c, const std::vector<double>& genes) =
      nullptr;
  void (*advance)(const Controller& c, const std::vector<double>& genes, double dt,
                  std::vector<double>& state) = nullptr;
  std::vector<double> (*state_commands)(const Controller& c, const std::vector<double>& genes,
                                        const std::vector<double>& state) = nullptr;
  // The gait periods (s) the kind can run; a genotype outside is an invalid evaluation
  // with the reason. Wider than any robot's gene range, so that studies may explore beyond.
  double min_period_s = 0, max_period_s = 1e300;
  // Numbers the descriptor must give (controller.<key>: a number, a parameter or a linear
  // expression of them, taken at the parameters' nominal values: the controller's own
  // model of the robot, as a real robot's controller has one; leg_gait: its leg lengths).
  std::vector<std::string> value_keys = {};
  // Its commands are the set-points followed by as many feed-forward torques (N m), which
  // PD servos add to their own torque (leg_gait: the stance legs carrying the body).
  bool feed_forward = false;
  // A feedback kind: its commands at t given the base's state (ControllerRun::At with a
  // state); without one it falls back to `commands`, its open-loop schedule.
  std::vector<double> (*feedback)(const Controller& c, const std::vector<double>& genes, double t,
                                  const BodyState& base) = nullptr;
  // Why a genotype cannot run ("" when it can), beyond its period: an invalid evaluation
  // with this reason rather than a gait the controller silently bends (leg_gait: a foot's
  // path out of its leg's reach).
  std::string (*check)(const Controller& c, const std::vector<double>& genes) = nullptr;
};

// The commands of one genotype over a run, asked in time order. A stateless kind is a
// function of time; a stateful one is integrated at a fixed internal step (1 ms, the state
// at the last step at or before t), so the commands at a time never depend on when, or how
// often, they were asked for.
class ControllerRun {
 public:
  static constexpr double kStep = 1e-3;  // s
  ControllerRun(const Controller& c, std::vector<double> genes);
  // Each actuator's command at t >= 0 (s), in the controller's order; t must not decrease
  // between calls. A feedback kind given the base's state closes its loop on it.
  std::vector<double> At(double t, const BodyState* base = nullptr);
  bool feedback() const { return kind_.feedback != nullptr; }
  // A stateful kind's state after the last At (cpg: the four phases, rad); else empty.
  const std::vector<double>& state() const { return state_; }

 private:
  const Controller& c_;
  const ControllerKind& kind_;
  std::vector<double> genes_, state_;
  long steps_ = 0;  // the state is at steps_ * kStep
};

const std::vector<ControllerKind>& ControllerKinds();
const ControllerKind* FindControllerKind(std::string_view name);  // nullptr when unknown
std::vector<std::string> ControllerKindNames();

}  // namespace gaitforge::robots
