#pragma once
// The leg_gait kind's closed loop (robots/leg_gait.h): paper 002's stance controller. The
// base's state gives a desired wrench (the weight, PD on roll, pitch and yaw rate, and on
// the velocity against the gait's speed); the stance feet's forces that best give it are
// the least-squares solution the paper's QP weights (S = diag(20, 20, 50, 450, 450, 450),
// a small regularisation), held inside a friction cone; each stance leg's joints get
// tau = -J^T f, J its foot's Jacobian in the base's frame.
#include <array>
#include <vector>

#include "robots/controllers.h"

namespace gaitforge::robots {

// A leg's foot in the base's frame (m, from the base's centre) at angles q (hip abduction
// about +x, thigh, calf: the URDF's), with its hip joint at `hip` and the thigh's plane
// `side` * offset outboard (side +1 left, -1 right), and the Jacobian's columns.
struct LegPoint {
  std::array<double, 3> foot{};
  std::array<std::array<double, 3>, 3> jacobian{};  // d foot / d q_j, per joint j
};
LegPoint LegKinematics(const std::array<double, 3>& hip, double side, double offset, double thigh,
                       double calf, const std::array<double, 3>& q);

// The ground's forces on the stance feet (world frame, N) that best give `wrench` (force
// then moment about the base's centre, world frame) with feet at `feet` (world-frame
// vectors from the base's centre), each within the friction cone `mu`.
std::vector<std::array<double, 3>> StanceForces(const std::vector<std::array<double, 3>>& feet,
                                                const std::array<double, 6>& wrench, double mu);

// The leg_gait kind's feedback commands: its schedule's set-points and, for each stance leg,
// the torques that push its share of the wrench the base's state asks for.
std::vector<double> LegGaitFeedback(const Controller& c, const std::vector<double>& genes,
                                    double t, const BodyState& base);

}  // namespace gaitforge::robots
