// Paper 004's continuum arm (robots/continuum_arm/robot.yaml) on the generic builder: it
// hangs straight, its rods bend it as T = B f says (every joint carries the rods' moment
// r sum f_k u_k x z, so each turns moment / k about each axis, towards the pulled rods),
// balanced rods leave it straight, and a force beyond max_force is clamped.
#include <cmath>
#include <string>
#include <vector>

#include "gtest/gtest.h"
#include "robots/descriptor_parser.h"
#include "robots/registry.h"
#include "workers/models/generic/generic_gait.h"
#include "workers/models/generic/generic_world.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::generic {
namespace {

const robots::RobotDescriptor& Arm() { return robots::Robot("continuum_arm"); }

class ContinuumArmTest : public ::testing::Test {
 protected:
  void SetUp() override { sim::InitThread(); }
};

// The arm after `seconds` with rod forces f (N), without gravity unless `gravity`, with
// the rods' max_force `max` (N; 0: the descriptor's).
std::unique_ptr<GenericWorld> Hold(const std::vector<double>& f, double seconds, bool gravity,
                                   double max = 0) {
  ParamValues v(Arm());
  if (!gravity) {
    EXPECT_TRUE(v.Set("simulation.gravity_m_per_s2", 0).ok());
  }
  if (max > 0) {
    EXPECT_TRUE(v.Set("rods.max_force_n", max).ok());
  }
  auto w = GenericWorld::Build(Arm(), v, 0);
  EXPECT_TRUE(w.ok()) << w.status();
  if (!w.ok()) return nullptr;
  const int steps = static_cast<int>(std::lround(seconds / (*w)->timestep()));
  for (int i = 0; i < steps; ++i) {
    const auto out = (*w)->Step(f);
    EXPECT_TRUE(out.ok) << out.reason;
    if (!out.ok) break;
  }
  return std::move(*w);
}

double Ch(const GenericWorld& w, const std::string& name) {
  auto v = w.Channel(name);
  EXPECT_TRUE(v.ok()) << v.status();
  return v.ok() ? *v : NAN;
}

TEST_F(ContinuumArmTest, HangsStraightUnderGravity) {
  const auto w = Hold({}, 2.0, true);
  ASSERT_TRUE(w);
  const ParamValues v(Arm());
  EXPECT_NEAR(Ch(*w, "tip.z"), -v("arm.length_m"), 1e-4);
  EXPECT_NEAR(Ch(*w, "tip.x"), 0, 1e-9);
  EXPECT_NEAR(Ch(*w, "tip.y"), 0, 1e-9);
  EXPECT_EQ(w->ground_contacts(), -1);  // no ground: contacts not known
}

// Paper 004's Table 2 forces (N), scaled to small bends: without gravity every joint
// carries the rods' moment M = r sum f_k (sin t_k, -cos t_k) and turns M_x / k_x about x
// and M_y / k_y about y; the tip moves towards the resultant of the pulled rods.
TEST_F(ContinuumArmTest, RodsBendEveryJointByTheirMomentOverItsStiffness) {
  const double scale = 0.2;
  const std::vector<double> f = {0.3025 * scale, 0.3263 * scale, -0.1265 * scale};
  const auto w = Hold(f, 6.0, false);
  ASSERT_TRUE(w);
  const ParamValues v(Arm());
  const double r = v("rods.radius_m");
  double mx = 0, my = 0;
  for (int k = 0; k < 3; ++k) {
    const double t = 2 * M_PI * k / 3;
    mx += r * f[k] * std::sin(t);
    my -= r * f[k] * std::cos(t);
  }
  const double psi_x = mx / v("joint.stiffness_x_nm_per_rad");
  const double psi_y = my / v("joint.stiffness_y_nm_per_rad");
  for (int j = 1; j <= 5; ++j) {
    const std::string name = "j" + std::to_string(j);
    EXPECT_NEAR(std::fabs(Ch(*w, name + ".angle1")), std::fabs(psi_x), 0.02 * std::fabs(psi_x)) << name;
    EXPECT_NEAR(std::fabs(Ch(*w, name + ".angle2")), std::fabs(psi_y), 0.02 * std::fabs(psi_y)) << name;
  }
  // Towards the resultant (within 2 degrees: k_x and k_y differ by 8%).
  const double resultant = std::atan2(f[1] * std::sin(2 * M_PI / 3) + f[2] * std::sin(4 * M_PI / 3),
                                      f[0] + f[1] * std::cos(2 * M_PI / 3) + f[2] * std::cos(4 * M_PI / 3));
  EXPECT_GT(Ch(*w, "tip.x"), 0);
  EXPECT_GT(Ch(*w, "tip.y"), 0);
  EXPECT_NEAR(std::atan2(Ch(*w, "tip.y"), Ch(*w, "tip.x")), resultant, 0.035);
}

// Another N is the same arm (counts.lumps; joint stiffness N / 5 times the paper's): rods 2
// and 3 pulled alike bend it about y only, each of the N joints by theta = M / k_N, and the
// tip lies at x = -(L / N) sum_i sin(i theta), z = -(L / N) sum_i cos(i theta): the chain's
// closed form, which tends to the continuum's L (1 - cos T) / T as N grows.
TEST_F(ContinuumArmTest, EveryNumberOfLumpsBendsAsItsChainsClosedForm) {
  const double f = 0.5;
  for (int n : {2, 5, 10, 20}) {
    std::string text(robots::BuiltinText("continuum_arm"));
    const std::string from = "lumps: {value: 5,";
    text.replace(text.find(from), from.size(), "lumps: {value: " + std::to_string(n) + ",");
    auto d = robots::ParseDescriptor(text, "arm.yaml");
    ASSERT_TRUE(d.ok()) << d.status();
    ParamValues v(*d);
    ASSERT_TRUE(v.Set("simulation.gravity_m_per_s2", 0).ok());
    auto w = GenericWorld::Build(*d, v, 0);
    ASSERT_TRUE(w.ok()) << w.status();
    for (int i = 0; i < 8000; ++i) ASSERT_TRUE((*w)->Step({0, f, f}).ok);
    // r f (sin t, -cos t) of rods at 120 and 240 degrees: (0, r f) together.
    const double m = v("rods.radius_m") * f;
    const double theta = m / (v("joint.stiffness_y_nm_per_rad") * n / 5.0);
    double x = 0, z = 0;
    for (int i = 1; i <= n; ++i) {
      x -= v("arm.length_m") / n * std::sin(i * theta);
      z -= v("arm.length_m") / n * std::cos(i * theta);
    }
    EXPECT_NEAR(Ch(**w, "tip.x"), x, 0.01 * std::fabs(x)) << "N = " << n;
    EXPECT_NEAR(Ch(**w, "tip.z"), z, 1e-4) << "N = " << n;
    EXPECT_NEAR(Ch(**w, "tip.y"), 0, 1e-9) << "N = " << n;
  }
}

TEST_F(ContinuumArmTest, BalancedRodsLeaveItStraightAndForceIsClamped) {
  const auto balanced = Hold({2, 2, 2}, 1.0, true);
  ASSERT_TRUE(balanced);
  EXPECT_NEAR(Ch(*balanced, "tip.x"), 0, 1e-9);
  EXPECT_NEAR(Ch(*balanced, "tip.y"), 0, 1e-9);
  // Beyond max_force (here 0.3 N) rod 1 pulls with 0.3 N: 3 N and 0.3 N bend it alike.
  const auto over = Hold({3, 0, 0}, 0.5, true, 0.3), at = Hold({0.3, 0, 0}, 0.5, true, 0.3);
  ASSERT_TRUE(over && at);
  EXPECT_EQ(Ch(*over, "tip.x"), Ch(*at, "tip.x"));
  EXPECT_GT(Ch(*at, "tip.x"), 0.005);  // towards rod 1, at +x
}

// No gait kind gives a tendon's force: a controller that names a rod is refused with why.
TEST_F(ContinuumArmTest, AGaitControllerCannotDriveARod) {
  std::string text(robots::BuiltinText("continuum_arm"));
  const std::string hold = "controller: {kind: hold, actuators: [rod1, rod2, rod3]}";
  text.replace(text.find(hold), hold.size(),
               "controller: {kind: phase_onoff, actuators: [rod1, rod2, rod3], period_s: [0.5, 2]}");
  auto d = robots::ParseDescriptor(text, "arm-onoff.yaml");
  ASSERT_TRUE(d.ok()) << d.status();
  const GaitResult r = EvaluateGait(*d, ParamValues(*d), {0, 0, 0, 0.5, 0.5, 0.5, 1.0});
  EXPECT_FALSE(r.valid);
  EXPECT_NE(r.reason.find("tendon rod1 cannot take"), std::string::npos) << r.reason;
}

}  // namespace
}  // namespace gaitforge::generic
