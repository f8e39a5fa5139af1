#pragma once
// One gait of a generic robot (model: generic): from rest, settle_cycles gait periods, then
// measured_cycles more; fitness is the forward (+x) travel of the robot's centre of mass
// over the measured cycles, per cycle (m). The controller kind (robots/controllers.h) turns
// the genes into each actuator's command over time; with effect.actuator_delay_s = d the
// actuators receive the command of time max(0, t - d).
#include <string>
#include <vector>

#include "robots/descriptor.h"
#include "workers/models/generic/generic_world.h"
#include "workers/objectives/recording_comparison.h"

namespace gaitforge::generic {

struct GaitOptions {
  int settle_cycles = -1;    // < 0: the robot's simulation.settle_cycles
  int measured_cycles = -1;  // < 0: the robot's simulation.measured_cycles
  double timestep_s = 0;     // <= 0: the robot's simulation.timestep_s
  double start_phase = 0;    // the gait's phase at t = 0 (cycles, 0..1)
  // > 0: measure a fixed time instead of cycles (paper 001): the fitness is the forward
  // travel of the centre of mass over duration_s from rest, start-up included (m).
  double duration_s = 0;
  // The engine that builds the world; empty: the ODE builder (GenericWorld).
  WorldBuilder engine = {};
};

struct GaitResult {
  bool valid = false;
  std::string reason;               // why not valid
  double distance_per_cycle_m = 0;  // the fitness (cycles)
  double travel_m = 0;              // the fitness (duration_s > 0)
  double simulated_s = 0;
  double max_tilt_rad = 0;            // GenericWorld::max_tilt over the whole run
  double torque_limited_fraction = 0; // GenericWorld::torque_limited_fraction
  double servo_energy_j = 0;          // over the measured part (cycles or duration_s)
  // A robot with an `electrical:` section (power_meter.h): the battery's energy over the
  // measured part (J) and that part's length (s); electrical false: none.
  bool electrical = false;
  double electrical_energy_j = 0, measured_s = 0;
  double weight_n = 0;                // total mass times gravity
  // Over the measured part: the largest |angle| of the line from the first body's centre
  // to the last one's against the ground (rad), the share of steps without a ground contact
  // (-1: the engine does not say), the pistons' work (J) and their largest extension beyond
  // min_length (m; 0 without pistons).
  double max_body_pitch_rad = 0;
  double airborne_fraction = 0;
  double piston_work_j = 0;
  double max_stroke_m = 0;
};

// Commands (rad) of each actuator, in descriptor order, at time t for these genes; an
// error when the controller kind cannot drive this robot's actuators.
absl::StatusOr<std::vector<double>> Commands(const robots::RobotDescriptor& d,
                                             const std::vector<double>& genes, double t);

// Places a command vector in the controller's actuator order into descriptor order: the
// mapping is worked out once, as a gait runs it every step.
class DescriptorOrder {
 public:
  explicit DescriptorOrder(const robots::RobotDescriptor& d);
  // out[slot of k] = command[k]; the other actuators 0. `out` is resized as needed. A
  // command with feed-forward torques after its set-points (twice as long) places them
  // after the descriptor's set-points: out[actuators + slot of k] = command[K + k].
  void Place(const std::vector<double>& command, std::vector<double>& out) const;
  std::vector<double> operator()(const std::vector<double>& command) const;

 private:
  size_t actuators_;
  std::vector<size_t> slot_;  // per controller actuator: its descriptor index
};

// The robot's channels (its sensors: robots::RobotDescriptor::Channels) sampled at rate_hz
// over `cycles` gait periods after `settle_cycles` from rest: from the step that starts the
// first measured cycle (t = 0 without settling), times counted from rest; rate_hz must give
// a whole number of timesteps (timestep_s <= 0: the robot's simulation.timestep_s) per
// sample.
calibration::SimRun SimulateChannels(const robots::RobotDescriptor& d, const ParamValues& values,
                                     const std::vector<double>& genes, int cycles, double rate_hz,
                                     double timestep_s = 0, const WorldBuilder& engine = {},
                                     int settle_cycles = 0);

// Never throws for a diverging model: that is valid = false with the reason.
GaitResult EvaluateGait(const robots::RobotDescriptor& d, const ParamValues& values,
                        const std::vector<double>& genes, const GaitOptions& options = {});

}  // namespace gaitforge::generic
