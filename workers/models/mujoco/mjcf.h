#pragma once
// A robot on the generic builder written as a MuJoCo model (MJCF), for an independent build
// of the same descriptor (mujoco_world.h). The translation, and what it cannot carry over:
//
// - Bodies: boxes and spheres with their mass and uniform inertia; the joints' second bodies
//   nested in their first (MuJoCo needs a tree: a body that is the second body of two joints
//   is refused), every root body on a free joint; a fixed joint nests its body without a
//   joint. Poses: the descriptor's start positions and pitches, made relative to the parent.
// - Hinges: the anchor and axis in the child's frame, the spring (stiffness, springref =
//   rest) and damper as MuJoCo's joint stiffness and damping, the stops as its range (in
//   radians: the model says <compiler angle="radian"/>, MJCF's default being degrees).
// - Servos: a velocity actuator (force limited to max_torque; kv reaching it at half of
//   max_speed of speed error) whose control MujocoWorld sets each step to the same lagged,
//   speed-limited command as the ODE builder's motor. A stiffer kv (the limit at 5%) made
//   the travel depend on the step: MuJoCo's implicit integration does not follow the
//   clamped force's derivative (Tigrillo, one gait: 0.35 / 0.19 / -0.19 m at 0.1 / 0.25 /
//   1 ms against 0.29 / 0.29 / 0.27 m with this kv). A PD servo (kp, kd) is a motor whose
//   torque MujocoWorld sets each step as the ODE build does, its feed-forward added.
// - Ground: a plane; only robot-ground contacts (no self-collision, as in the ODE build);
//   each box's Coulomb coefficient (its own or the ground's; MuJoCo takes the larger of
//   the two geoms', the plane's is 0); a contact depth d lowers the box's contact geometry
//   by d (its bottom face, in the body's frame). MuJoCo's soft contact (solref 5 ms,
//   critically damped) with an elliptic friction cone and impratio 10 (less creep of a
//   loaded foot) stands for ODE's ERP/CFM contact; the ground's friction_load rule has no
//   counterpart.
// - Integrator: implicit in velocity (the stiff servos and dampers), the robot's timestep.
#include <string>

#include "absl/status/statusor.h"
#include "robots/descriptor.h"
#include "workers/models/generic/generic_world.h"

namespace gaitforge::mujoco {

// The MJCF text of robot d with values v, stepped at timestep_s (<= 0: the robot's own).
// InvalidArgument when the structure is not a tree or a value makes no physical sense.
absl::StatusOr<std::string> ToMjcf(const robots::RobotDescriptor& d, const generic::ParamValues& v,
                                   double timestep_s);

}  // namespace gaitforge::mujoco
