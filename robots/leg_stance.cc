#include "robots/leg_stance.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

#include "robots/leg_gait.h"

namespace gaitforge::robots {

LegPoint LegKinematics(const std::array<double, 3>& hip, double side, double offset, double thigh,
                       double calf, const std::array<double, 3>& q) {
  const double s1 = std::sin(q[1]), c1 = std::cos(q[1]);
  const double s12 = std::sin(q[1] + q[2]), c12 = std::cos(q[1] + q[2]);
  const double ca = std::cos(q[0]), sa = std::sin(q[0]);
  // About +x by the abduction: (x, y, z) -> (x, ca y - sa z, sa y + ca z).
  auto rot = [&](double x, double y, double z) { return std::array<double, 3>{x, ca * y - sa * z, sa * y + ca * z}; };
  const auto leg = rot(-thigh * s1 - calf * s12, side * offset, -thigh * c1 - calf * c12);
  LegPoint p;
  for (int k = 0; k < 3; ++k) p.foot[k] = hip[k] + leg[k];
  p.jacobian[0] = {0, -leg[2], leg[1]};  // x-hat cross the leg
  p.jacobian[1] = rot(-thigh * c1 - calf * c12, 0, thigh * s1 + calf * s12);
  p.jacobian[2] = rot(-calf * c12, 0, calf * s12);
  return p;
}

std::vector<std::array<double, 3>> StanceForces(const std::vector<std::array<double, 3>>& feet,
                                                const std::array<double, 6>& wrench, double mu) {
  const int n = static_cast<int>(feet.size());
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(6, 3 * n);
  for (int i = 0; i < n; ++i) {
    const auto& r = feet[i];
    a.block<3, 3>(0, 3 * i).setIdentity();
    a.block<3, 3>(3, 3 * i) << 0, -r[2], r[1], r[2], 0, -r[0], -r[1], r[0], 0;  // r x
  }
  const Eigen::VectorXd s = (Eigen::VectorXd(6) << 20, 20, 50, 450, 450, 450).finished();
  const Eigen::VectorXd b = Eigen::Map<const Eigen::VectorXd>(wrench.data(), 6);
  const Eigen::MatrixXd h = a.transpose() * s.asDiagonal() * a +
                            1e-4 * Eigen::MatrixXd::Identity(3 * n, 3 * n);
  const Eigen::VectorXd f = h.ldlt().solve(a.transpose() * s.asDiagonal() * b);
  std::vector<std::array<double, 3>> out(n);
  for (int i = 0; i < n; ++i) {
    const double fz = std::max(0.0, f(3 * i + 2));  // the ground only pushes
    double fx = f(3 * i), fy = f(3 * i + 1);
    const double along = std::hypot(fx, fy), most = mu * fz;
    if (along > most) {  // onto the cone's edge
      fx *= most / along;
      fy *= most / along;
    }
    out[i] = {fx, fy, fz};
  }
  return out;
}

namespace {

// Body frame to world (row-major rotation) and back.
std::array<double, 3> ToWorld(const BodyState& b, const std::array<double, 3>& v) {
  const auto& r = b.rotation;
  return {r[0] * v[0] + r[1] * v[1] + r[2] * v[2], r[3] * v[0] + r[4] * v[1] + r[5] * v[2],
          r[6] * v[0] + r[7] * v[1] + r[8] * v[2]};
}
std::array<double, 3> ToBody(const BodyState& b, const std::array<double, 3>& v) {
  const auto& r = b.rotation;
  return {r[0] * v[0] + r[3] * v[1] + r[6] * v[2], r[1] * v[0] + r[4] * v[1] + r[7] * v[2],
          r[2] * v[0] + r[5] * v[1] + r[8] * v[2]};
}

// The wrench the base's state asks for (world frame): the carried weight, PD on roll and
// pitch, damping of yaw and of vertical motion, and the velocity along the heading pulled
// to the gait's speed, across it to 0.
std::array<double, 6> DesiredWrench(const BodyState& b, double mass, double load, double speed) {
  const auto& r = b.rotation;
  const double roll = std::atan2(r[7], r[8]), pitch = -std::asin(std::clamp(r[6], -1.0, 1.0));
  const double yaw = std::atan2(r[3], r[0]);
  const double hx = std::cos(yaw), hy = std::sin(yaw);
  const double along = b.velocity[0] * hx + b.velocity[1] * hy;
  const double across = -b.velocity[0] * hy + b.velocity[1] * hx;
  constexpr double kVel = 10.0, kVz = 10.0;      // 1/s
  constexpr double kAtt = 150, dAtt = 15, dYaw = 10;  // N m/rad, N m s/rad
  const double fa = mass * kVel * (speed - along), fc = -mass * kVel * across;
  // Roll and pitch as small rotations about the heading's axes, turned into the world.
  const double mr = -kAtt * roll, mp = -kAtt * pitch;
  return {fa * hx - fc * hy,
          fa * hy + fc * hx,
          load * mass * kStandardGravity - mass * kVz * b.velocity[2],
          mr * hx - mp * hy - dAtt * b.spin[0],
          mr * hy + mp * hx - dAtt * b.spin[1],
          -dYaw * b.spin[2]};
}

}  // namespace

std::vector<double> LegGaitFeedback(const Controller& c, const std::vector<double>& g, double t,
                                    const BodyState& base) {
  const LegSchedule s = Schedule(c, g, t);
  std::vector<double> out(s.commands.begin(), s.commands.end());
  out.resize(24, 0.0);
  if (s.on_ground == 0) return out;
  const double l1 = c.values.at("thigh_m"), l2 = c.values.at("calf_m");
  std::vector<int> legs;
  std::vector<LegPoint> points;
  std::vector<std::array<double, 3>> feet;
  for (int leg = 0; leg < 4; ++leg) {
    if (!s.stance[leg]) continue;
    const bool front = leg < 2, left = leg % 2 == 1;
    const std::array<double, 3> hip = {c.values.at(front ? "front_hip_x_m" : "rear_hip_x_m"),
                                       (left ? 1 : -1) * c.values.at("hip_y_m"), c.values.at("hip_z_m")};
    points.push_back(LegKinematics(hip, left ? 1 : -1, c.values.at("hip_offset_m"), l1, l2,
                                   {0, s.q[leg][0], s.q[leg][1]}));
    feet.push_back(ToWorld(base, points.back().foot));
    legs.push_back(leg);
  }
  const auto forces = StanceForces(
      feet, DesiredWrench(base, c.values.at("mass_kg"), g[5], g[3]), 0.6);
  for (size_t i = 0; i < legs.size(); ++i) {
    const auto f = ToBody(base, forces[i]);
    for (int j = 0; j < 3; ++j) {
      const auto& col = points[i].jacobian[j];
      out[12 + 3 * legs[i] + j] = -(col[0] * f[0] + col[1] * f[1] + col[2] * f[2]);
    }
  }
  return out;
}

}  // namespace gaitforge::robots
