#pragma once
// A robot on the generic builder as a physics engine steps it: what a gait run, a
// recording's channels and the gait metrics read, whichever engine built the world. The ODE
// builder (generic_world.h) is the one studies use; workers/models/mujoco/ builds the same
// descriptor in MuJoCo, an independent build for comparisons (bench/mujoco_compare.cc) and
// reference recordings.
#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "robots/controllers.h"
#include "robots/descriptor.h"
#include "workers/sim/sim_outcome.h"

namespace gaitforge::generic {

class ParamValues;

class RobotWorld {
 public:
  virtual ~RobotWorld() = default;
  // One step with `commands[i]` the angle (rad) commanded to actuator i (descriptor order).
  // !ok once the state diverged: do not step again.
  virtual sim::SimOutcome Step(const std::vector<double>& commands) = 0;
  virtual double time() const = 0;
  virtual double timestep() const = 0;
  // The mass-weighted mean of the bodies' centres (m, world frame).
  virtual std::array<double, 3> CentreOfMass() const = 0;
  // The value of a recording channel ("hinge.angle", "tip.x"); NotFound for another.
  virtual absl::StatusOr<double> Channel(const std::string& name) const = 0;
  // The largest tilt of the first body (roll or pitch, rad) over the steps so far.
  virtual double max_tilt() const = 0;
  // Of the servo-steps so far, the fraction at >= 99% of the servo's max_torque.
  virtual double torque_limited_fraction() const = 0;
  // The servos' positive mechanical work so far (J).
  virtual double servo_energy() const = 0;
  // Per actuator (descriptor order), after the last step: the torque its servo put on the
  // joint (N m, positive turning the joint's angle up) and the joint's rate (rad/s); 0 for
  // pistons and tendons. Their product is the servo's mechanical power.
  virtual const std::vector<double>& actuator_torques() const = 0;
  virtual const std::vector<double>& actuator_rates() const = 0;
  // The channel "<actuator>.torque" or "<actuator>.rate" of d's servo actuator `base`
  // (joint_torque and joint_rate sensors) from the two above; nullopt for another name.
  std::optional<double> ActuatorChannel(const robots::RobotDescriptor& d, const std::string& base,
                                        const std::string& field) const {
    if (field != "torque" && field != "rate") return std::nullopt;
    for (size_t i = 0; i < d.actuators.size(); ++i)
      if (d.actuators[i].name == base && d.actuators[i].type == "servo")
        return field == "torque" ? actuator_torques()[i] : actuator_rates()[i];
    return std::nullopt;
  }
  virtual double total_mass() const = 0;
  // A descriptor body's centre (m, world frame; the mean of its halves when split).
  virtual std::array<double, 3> BodyCentre(int body) const = 0;
  // A descriptor body's centre, rotation and velocities (its first half's when split), what
  // a feedback controller reads of the base (robots::BodyState).
  virtual robots::BodyState StateOf(int body) const = 0;
  // Ground contacts in the last step; -1 when the engine does not say.
  virtual int ground_contacts() const { return -1; }
  // Pistons (engines that build them): the work of their pushes in the last step (J; each
  // push times its change of length) and their extensions beyond min_length after the last
  // step (m).
  virtual double last_piston_work() const { return 0; }
  virtual const std::vector<double>& piston_extensions() const {
    static const std::vector<double> none;
    return none;
  }
};

// Builds descriptor d with these values at rest (timestep_s <= 0: the robot's own).
using WorldBuilder = std::function<absl::StatusOr<std::unique_ptr<RobotWorld>>(
    const robots::RobotDescriptor& d, const ParamValues& values, double timestep_s)>;

}  // namespace gaitforge::generic
