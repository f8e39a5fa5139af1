// The leg_gait controller kind (robots/leg_gait.h): its two-link inverse kinematics, the
// stance torques that hold a foot's load, and the phase patterns of a trot and paper 002's
// slide, on the Go2's controller section (robots/go2_castors/robot.yaml).
#include <cmath>
#include <string>
#include <vector>

#include "gtest/gtest.h"
#include "robots/leg_gait.h"
#include "robots/leg_stance.h"
#include "robots/registry.h"

namespace gaitforge::robots {
namespace {

constexpr double kL1 = 0.213, kL2 = 0.213;

std::array<double, 2> Foot(const std::array<double, 2>& q) {
  return {-kL1 * std::sin(q[0]) - kL2 * std::sin(q[0] + q[1]),
          -kL1 * std::cos(q[0]) - kL2 * std::cos(q[0] + q[1])};
}

TEST(LegGait, InverseKinematicsPutsTheFootWhereAsked) {
  // The Go2's stand (thigh 0.8, calf -1.5) and other reachable points, knee folded back.
  const auto stand = Foot({0.8, -1.5});
  const auto q = LegAngles(kL1, kL2, stand[0], stand[1]);
  EXPECT_NEAR(q[0], 0.8, 1e-9);
  EXPECT_NEAR(q[1], -1.5, 1e-9);
  for (auto [x, z] : {std::pair{0.1, -0.25}, std::pair{-0.12, -0.2}, std::pair{0.05, -0.09}}) {
    const auto a = LegAngles(kL1, kL2, x, z);
    EXPECT_LT(a[1], 0);
    const auto f = Foot(a);
    EXPECT_NEAR(f[0], x, 1e-9);
    EXPECT_NEAR(f[1], z, 1e-9);
  }
  // Out of reach: the leg stretches towards the target, nothing undefined.
  const auto far = Foot(LegAngles(kL1, kL2, 0, -0.6));
  EXPECT_NEAR(far[0], 0, 1e-6);
  EXPECT_NEAR(far[1], -(kL1 + kL2), 1e-6);
}

TEST(LegGait, StanceTorquesDoTheVirtualWorkOfTheFootsLoad) {
  // tau . dq = -f . dp for any small motion: the torques balance the ground's push f.
  const std::array<double, 2> q = {0.8, -1.5};
  const double force = 38;
  const auto tau = StanceTorques(kL1, kL2, q, force);
  for (int j = 0; j < 2; ++j) {
    std::array<double, 2> q2 = q;
    q2[j] += 1e-7;
    const double dz = Foot(q2)[1] - Foot(q)[1];
    EXPECT_NEAR(tau[j] * 1e-7, -force * dz, 1e-10) << j;
  }
  EXPECT_NEAR(tau[1], force * kL2 * std::sin(0.7), 1e-9);  // the knee unfolds against it
}

TEST(LegGait, TrotAndSlideArePhasePatternsWithTheWeightOnTheStanceFeet) {
  const Controller& c = Robot("go2_castors").controller;
  ASSERT_EQ(c.kind, "leg_gait");
  const double stand = kL1 * std::cos(0.8) + kL2 * std::cos(0.7);
  // T, stance, lift, speed, height, load, lr, fh: standing in place holds the stand.
  const auto held = LegGaitCommands(c, {0.6, 0.5, 0, 0, stand, 1, 0.5, 0.5}, 0.1);
  ASSERT_EQ(held.size(), 24u);
  for (int i = 0; i < 12; ++i) EXPECT_NEAR(held[i], 0, 1e-6) << i;
  // A trot: FR and RL on the ground together, FL and RR in the air (lifted: calf folded).
  const auto trot = LegGaitCommands(c, {0.6, 0.5, 0.08, 0.22, stand, 1, 0.5, 0.5}, 0.1);
  const double weight = c.values.at("mass_kg") * kStandardGravity;
  for (int leg : {0, 3}) EXPECT_GT(trot[12 + 3 * leg + 2], 0.1 * weight * kL2 / 2) << leg;
  for (int leg : {1, 2}) {
    EXPECT_EQ(trot[12 + 3 * leg + 2], 0) << leg;
    EXPECT_LT(trot[3 * leg + 2], -0.05) << leg;
  }
  // The slide: left and right in phase, the front half a cycle after the rear.
  const auto slide = LegGaitCommands(c, {0.8, 0.6, 0.03, 0.16, 0.1, 0.3, 0, 0.5}, 0.3);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(slide[i], slide[3 + i], 1e-12);  // FR = FL
    EXPECT_NEAR(slide[6 + i], slide[9 + i], 1e-12);  // RR = RL
  }
}

// Bad input: a foot path beyond the leg's reach is refused with where and by how much,
// not bent silently by the inverse kinematics.
TEST(LegGait, AFootPathOutOfReachIsRefusedSayingWhere) {
  const Controller& c = Robot("go2_castors").controller;
  EXPECT_EQ(LegGaitCheck(c, {0.6, 0.5, 0.08, 0.22, 0.30, 1, 0.5, 0.5}), "");
  const std::string deep = LegGaitCheck(c, {1.5, 0.8, 0.12, 0.5, 0.40, 1, 0.5, 0.5});
  EXPECT_NE(deep.find("at the stance stroke's front end"), std::string::npos) << deep;
  EXPECT_NE(deep.find("the leg reaches 0 to 0.426 m"), std::string::npos) << deep;
}

}  // namespace
}  // namespace gaitforge::robots

namespace gaitforge::robots {
namespace {

TEST(LegStance, TheLegsJacobianIsItsFootsDerivative) {
  const std::array<double, 3> hip = {0.17, 0.0465, 0.005};
  for (const std::array<double, 3> q : {std::array<double, 3>{0, 0.8, -1.5}, {0.2, 0.5, -1.9}}) {
    const LegPoint p = LegKinematics(hip, 1, 0.0955, 0.213, 0.213, q);
    for (int j = 0; j < 3; ++j) {
      auto q2 = q;
      q2[j] += 1e-7;
      const LegPoint moved = LegKinematics(hip, 1, 0.0955, 0.213, 0.213, q2);
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR((moved.foot[k] - p.foot[k]) / 1e-7, p.jacobian[j][k], 1e-6) << j << " " << k;
    }
  }
  // Unabducted, the foot lies in the leg's plane, offset outboard, where the planar legs put it.
  const LegPoint stand = LegKinematics(hip, 1, 0.0955, 0.213, 0.213, {0, 0.8, -1.5});
  EXPECT_NEAR(stand.foot[1], 0.0465 + 0.0955, 1e-12);
  EXPECT_NEAR(stand.foot[2] - 0.005, -0.213 * (std::cos(0.8) + std::cos(0.7)), 1e-12);
}

TEST(LegStance, StanceForcesGiveTheAskedWrenchWithinTheCone) {
  // Four feet around the centre, 0.2 m below: any modest wrench is met exactly (up to the
  // regularisation), the weight shared evenly.
  const std::vector<std::array<double, 3>> feet = {
      {0.2, -0.15, -0.3}, {0.2, 0.15, -0.3}, {-0.2, -0.15, -0.3}, {-0.2, 0.15, -0.3}};
  const std::array<double, 6> weight = {0, 0, 150, 0, 0, 0};
  for (const auto& f : StanceForces(feet, weight, 0.6)) EXPECT_NEAR(f[2], 37.5, 1e-3);
  const std::array<double, 6> push = {10, -5, 150, 3, -2, 1};
  const auto forces = StanceForces(feet, push, 0.6);
  std::array<double, 6> got{};
  for (size_t i = 0; i < feet.size(); ++i) {
    const auto& r = feet[i];
    const auto& f = forces[i];
    for (int k = 0; k < 3; ++k) got[k] += f[k];
    got[3] += r[1] * f[2] - r[2] * f[1];
    got[4] += r[2] * f[0] - r[0] * f[2];
    got[5] += r[0] * f[1] - r[1] * f[0];
  }
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(got[k], push[k], 0.01) << k;
  // A sideways push beyond friction is cut to the cone's edge; the ground never pulls.
  const auto slip = StanceForces(feet, {200, 0, 100, 0, 0, 0}, 0.6);
  for (const auto& f : slip) {
    EXPECT_GE(f[2], 0);
    EXPECT_LE(std::hypot(f[0], f[1]), 0.6 * f[2] + 1e-9);
  }
}

}  // namespace
}  // namespace gaitforge::robots
