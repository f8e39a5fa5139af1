#pragma once
// The electrical power a robot's motors draw from its battery (robots::Electrical; docs/
// robots.md, "Electrical"), step by step from each servo's torque and its joint's rate:
// paper 002's P_E = V_b I, whose cost of transport is P_E / (m g v). Either the motors'
// model (gear, torque constant, winding resistance) or a learned current model (paper
// 002's MLP from the joints' torques and rates to the battery's current).
#include <memory>
#include <vector>

#include "absl/status/statusor.h"
#include "robots/descriptor.h"
#include "workers/learned/mlp.h"

namespace gaitforge::generic {

class ParamValues;

class PowerMeter {
 public:
  // The meter of d's `electrical:` section with these values; nullptr when d has none. An
  // error names a current model that cannot be read or whose inputs and output are not
  // the robot's servos' torques and rates and "bus.current".
  static absl::StatusOr<std::unique_ptr<PowerMeter>> For(const robots::RobotDescriptor& d,
                                                         const ParamValues& v);

  // The battery's power (W) for these torques (N m) and joint rates (rad/s), one per actuator
  // in descriptor order. The motors' model: each motor's tau w + 1.5 R (tau / (gear kt))^2,
  // summed on the bus with the standby power, a bus that brakes (< 0) returning
  // regen_efficiency of it. A learned model: bus_voltage times its current.
  double Power(const std::vector<double>& torque, const std::vector<double>& rate) const;
  // Adds a step of h seconds at Power(torque, rate). A learned model is asked at its
  // current_model_rate_hz in simulated time (the first step, then once a period has
  // passed), its power held between.
  void Step(const std::vector<double>& torque, const std::vector<double>& rate, double h);

  double energy_j() const { return energy_j_; }  // since construction or the last Reset
  double seconds() const { return seconds_; }
  double bus_voltage() const { return voltage_; }
  bool learned() const { return mlp_ != nullptr; }
  void Reset() { energy_j_ = seconds_ = next_sample_s_ = 0; }

 private:
  struct Drive {
    int actuator = 0;
    double gear = 1, kt = 1, resistance = 0;
  };
  double MotorPower(const std::vector<double>& torque, const std::vector<double>& rate) const;
  absl::Status UseModel(const robots::RobotDescriptor& d);
  std::vector<Drive> drives_;
  double voltage_ = 0, standby_ = 0, regen_ = 0;
  // The learned model and, per input, its actuator and whether it reads the rate.
  std::shared_ptr<const learned::Mlp> mlp_;
  std::vector<std::pair<int, bool>> inputs_;
  mutable Eigen::VectorXd x_;
  double sample_period_s_ = 0, held_power_ = 0, next_sample_s_ = 0;
  double energy_j_ = 0, seconds_ = 0;
};

// A robot's learned current model, read once per process (robots::Electrical's
// current_model); the error names the file and what is wrong.
absl::StatusOr<std::shared_ptr<const learned::Mlp>> CurrentModel(const robots::RobotDescriptor& d);

}  // namespace gaitforge::generic
