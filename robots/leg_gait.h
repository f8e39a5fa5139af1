#pragma once
// The leg_gait controller kind (docs/robots.md, "controller"): a gait scheduler for a
// quadruped whose legs are a hip abduction joint and a thigh and a calf swinging in the
// leg's plane (the Go2's, paper 002): each foot follows a straight stance stroke backwards
// and a cycloid swing forwards, and the leg's two-link inverse kinematics turns its path into
// thigh and calf set-points. Trot and paper 002's slide are two phase patterns of it.
#include <array>
#include <string>
#include <vector>

#include "robots/descriptor.h"

namespace gaitforge::robots {

// A leg's thigh and calf angles (rad, the URDF's: about +y from the straight-down leg,
// the calf relative to the thigh and folded backwards, < 0) that put the foot at (x, z),
// m from the thigh joint in the leg's plane (x forward, z up). A target out of reach is
// pulled onto the reachable annulus along its own direction.
std::array<double, 2> LegAngles(double thigh_m, double calf_m, double x, double z);

// The kind's genes: T (s), stance (share of the cycle on the ground), lift (m), speed (m/s,
// the stance stroke's), height (m, the thigh joints over the feet in stance), load (the
// share of the weight the stance feet carry: 1 on feet alone, less on castors), lr
// (left-right phase, cycles), fh (front-rear phase, cycles).
std::vector<Gene> LegGaitGenes(const Controller& c);
double LegGaitPeriod(const std::vector<double>& genes);
// Why the genes' foot path leaves a leg's reach ("" when it does not): a stance stroke's end
// or the swing's apex farther from the thigh joint than thigh + calf, or nearer than their
// difference.
std::string LegGaitCheck(const Controller& c, const std::vector<double>& genes);
// Where the schedule puts each leg at t: on the ground or not, its thigh and calf angles
// (the URDF's), and the twelve set-points (measured from the stand; hips 0).
struct LegSchedule {
  std::array<bool, 4> stance{};
  int on_ground = 0;
  std::array<std::array<double, 2>, 4> q{};
  std::array<double, 12> commands{};
};
LegSchedule Schedule(const Controller& c, const std::vector<double>& genes, double t);

// The controller's standard gravity (m/s^2): its own model of the robot's weight.
inline constexpr double kStandardGravity = 9.80665;

// The joint torques (thigh, calf; N m, turning the angles up) that hold a push `force` (N)
// of the ground up on the foot of a leg at angles q.
std::array<double, 2> StanceTorques(double thigh_m, double calf_m, const std::array<double, 2>& q,
                                    double force);

// Twelve set-points, legs FR, FL, RR, RL (the Unitree order) x (hip, thigh, calf), each
// measured from the stand the controller's values name (thigh_stand_rad, calf_stand_rad),
// then twelve feed-forward torques: each stance leg's share of the weight (mass_kg).
std::vector<double> LegGaitCommands(const Controller& c, const std::vector<double>& genes,
                                    double t);

}  // namespace gaitforge::robots
