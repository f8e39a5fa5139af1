#pragma once
// The same descriptor built in MuJoCo (2.2.2, Debian's libmujoco-dev): an independent build
// of a robot on the generic builder, behind the interface gait runs use (RobotWorld). The
// model comes from ToMjcf (mjcf.h, which says what carries over); the servos are stepped as
// in the ODE builder: the effect's lag, the servo's own lag, the deadband, then a velocity
// command gain * error clamped to max_speed, which a force-limited velocity actuator
// follows. Effects: ground slope, tether and drag carry over; direction-dependent friction
// does not (refused when set).
#include <memory>
#include <string>
#include <vector>

#include "workers/models/generic/generic_world.h"
#include "workers/models/generic/robot_world.h"

struct mjModel_;
struct mjData_;

namespace gaitforge::mujoco {

class MujocoWorld : public generic::RobotWorld {
 public:
  static absl::StatusOr<std::unique_ptr<MujocoWorld>> Build(const robots::RobotDescriptor& d,
                                                            const generic::ParamValues& v,
                                                            double timestep_s);
  ~MujocoWorld() override;
  MujocoWorld(const MujocoWorld&) = delete;
  MujocoWorld& operator=(const MujocoWorld&) = delete;

  sim::SimOutcome Step(const std::vector<double>& commands) override;
  double time() const override { return steps_ * h_; }
  double timestep() const override { return h_; }
  std::array<double, 3> CentreOfMass() const override;
  absl::StatusOr<double> Channel(const std::string& name) const override;
  double max_tilt() const override { return max_tilt_; }
  double torque_limited_fraction() const override;
  double servo_energy() const override { return servo_energy_; }
  const std::vector<double>& actuator_torques() const override { return actuator_torque_; }
  const std::vector<double>& actuator_rates() const override { return actuator_rate_; }
  double total_mass() const override;
  // Body i's (descriptor order) centre, world frame (m).
  std::array<double, 3> BodyPosition(int i) const;
  std::array<double, 3> BodyCentre(int i) const override { return BodyPosition(i); }
  robots::BodyState StateOf(int i) const override;
  // The world position of joint j's (descriptor order) anchor as MuJoCo holds it (m).
  std::array<double, 3> JointAnchor(int j) const;

 private:
  MujocoWorld(const robots::RobotDescriptor& d, const generic::ParamValues& v, double h)
      : d_(d), h_(h), fx_(v) {}
  void SetServos(const std::vector<double>& commands);
  void ApplyEffects();
  sim::SimOutcome CheckState() const;
  void Observe();

  struct Servo {
    int joint = 0, qpos = 0, dof = 0;  // MuJoCo indexes
    double gain = 0, max_speed = 0, max_torque = 0, lag_keep = 0, extra_keep = 0;
    bool pd = false;  // a PD torque (kp, kd) instead of a speed command
    double kp = 0, kd = 0;
    double extra = 0, command = 0;
  };
  struct Marker {
    std::string name;
    int body = 0;  // MuJoCo body id
    std::array<double, 3> offset{};
  };
  const robots::RobotDescriptor& d_;
  const double h_;
  mjModel_* m_ = nullptr;
  mjData_* data_ = nullptr;
  std::vector<int> body_ids_;  // descriptor order -> MuJoCo body id
  std::vector<Servo> servos_;
  std::vector<Marker> markers_;
  std::vector<std::array<double, 3>> start_;
  const generic::BuilderEffects fx_;
  double max_speed_ = 0, max_excursion_ = 0;
  int64_t steps_ = 0, torque_limited_ = 0;
  double max_tilt_ = 0, servo_energy_ = 0;
  std::vector<double> actuator_torque_, actuator_rate_;  // per actuator, the last step's
};

// The builder gait runs take (generic::GaitOptions::engine, SimulateChannels).
generic::WorldBuilder Engine();

}  // namespace gaitforge::mujoco
