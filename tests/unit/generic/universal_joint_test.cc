// Universal joints and a chain held by the world on the generic builder, on a fixture that
// exists only as data (tests/fixtures/robots/cantilever/robot.yaml): gravity bends the
// chain as a lumped cantilever's closed form says, and its free vibration decays with the
// damping ratio its joints' dampers give.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "gtest/gtest.h"
#include "robots/descriptor_parser.h"
#include "tests/support/fixture_robot.h"
#include "workers/models/generic/generic_world.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::generic {
namespace {

const robots::RobotDescriptor& Cantilever() { return testing::FixtureRobot("cantilever"); }

// The tip's height (m) after each step of `seconds` from the straight start.
std::vector<double> TipHeights(const ParamValues& v, double seconds) {
  auto w = GenericWorld::Build(Cantilever(), v, 0);
  EXPECT_TRUE(w.ok()) << w.status();
  std::vector<double> z;
  if (!w.ok()) return z;
  const int steps = static_cast<int>(std::lround(seconds / (*w)->timestep()));
  for (int i = 0; i < steps; ++i) {
    const auto out = (*w)->Step({});
    EXPECT_TRUE(out.ok) << out.reason;
    if (!out.ok) break;
    z.push_back(*(*w)->Channel("tip.z"));
  }
  return z;
}

class UniversalJointTest : public ::testing::Test {
 protected:
  void SetUp() override { sim::InitThread(); }
};

// The fixture's text with every `from` replaced by `to`.
std::string Edited(const std::vector<std::pair<std::string, std::string>>& edits) {
  std::ifstream in(std::string(GAITFORGE_SOURCE_DIR) + "/tests/fixtures/robots/cantilever/robot.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  for (const auto& [from, to] : edits)
    for (size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size()))
      s.replace(p, from.size(), to);
  return s;
}

// Small deflection of N equal links (length L, mass m, centres at (j + 1/2) L) on joints
// at i L with stiffness k: joint i carries tau_i = sum_{j >= i} m g ((j + 1/2) L - i L),
// turns tau_i / k, and the tip drops sum_i (tau_i / k) (N L - i L). `bent` is the angle
// channel gravity turns, `k_param` its stiffness, `straight` the other, which stays 0.
void ExpectCantilever(const robots::RobotDescriptor& d, const std::string& bent,
                      const std::string& straight, const std::string& k_param) {
  ParamValues v(d);
  ASSERT_TRUE(v.Set("joint.bend_damping_nms_per_rad", 0.01).ok());  // settle quickly
  ASSERT_TRUE(v.Set("joint.side_damping_nms_per_rad", 0.01).ok());
  auto w = GenericWorld::Build(d, v, 0);
  ASSERT_TRUE(w.ok()) << w.status();
  for (int i = 0; i < 6000; ++i) ASSERT_TRUE((*w)->Step({}).ok);  // 3 s
  const double L = v("link.length_m"), m = v("link.mass_kg"), k = v(k_param);
  const double g = v("simulation.gravity_m_per_s2");
  const int n = 3;
  double drop = 0;
  for (int i = 0; i < n; ++i) {
    double tau = 0;
    for (int j = i; j < n; ++j) tau += m * g * ((j + 0.5) * L - i * L);
    const std::string joint = "j" + std::to_string(i + 1);
    EXPECT_NEAR(std::fabs(*(*w)->Channel(joint + "." + bent)), tau / k, 0.01 * tau / k) << joint;
    if (!straight.empty()) {
      EXPECT_NEAR(*(*w)->Channel(joint + "." + straight), 0, 1e-6) << joint;
    }
    drop += tau / k * (n * L - i * L);
  }
  EXPECT_NEAR(v("height_m") - *(*w)->Channel("tip.z"), drop, 0.02 * drop);
  EXPECT_NEAR(*(*w)->Channel("tip.y"), 0, 1e-6);
  // Every joint turns the same way: the chain curls down, it does not zigzag.
  EXPECT_GT(*(*w)->Channel("j1." + bent) * *(*w)->Channel("j3." + bent), 0);
}

TEST_F(UniversalJointTest, GravityBendsTheChainAsTheLumpedCantileverSays) {
  ExpectCantilever(Cantilever(), "angle1", "angle2", "joint.bend_stiffness_nm_per_rad");
}

// With the two axes swapped (axis about z, axis2 about y) gravity bends the chain about
// each joint's second axis, with the second stiffness.
TEST_F(UniversalJointTest, TheSecondAxisBendsWithItsOwnStiffness) {
  auto d = robots::ParseDescriptor(
      Edited({{"axis: [0, 1, 0], axis2: [0, 0, 1]", "axis: [0, 0, 1], axis2: [0, 1, 0]"}}),
      "cantilever-swapped.yaml");
  ASSERT_TRUE(d.ok()) << d.status();
  ExpectCantilever(*d, "angle2", "angle1", "joint.side_stiffness_nm_per_rad");
}

// The same chain on hinges about y, the first held by the world.
TEST_F(UniversalJointTest, AHingeHeldByTheWorldBendsTheSameWay) {
  auto d = robots::ParseDescriptor(
      Edited({{"type: universal", "type: hinge"},
              {" axis2: [0, 0, 1],", ""},
              {"[joint.bend_stiffness_nm_per_rad, joint.side_stiffness_nm_per_rad]",
               "joint.bend_stiffness_nm_per_rad"},
              {"[joint.bend_damping_nms_per_rad, joint.side_damping_nms_per_rad]",
               "joint.bend_damping_nms_per_rad"}}),
      "cantilever-hinges.yaml");
  ASSERT_TRUE(d.ok()) << d.status();
  ExpectCantilever(*d, "angle", "", "joint.bend_stiffness_nm_per_rad");
}

// Dampers proportional to the springs (c/k the same at every joint) give each mode the
// damping ratio zeta = (c / k) omega / 2: the first mode's, measured from the tip's free
// vibration about its rest (period and logarithmic decrement), must match it.
TEST_F(UniversalJointTest, FreeVibrationDecaysWithTheDampersRatio) {
  ParamValues v(Cantilever());
  const std::vector<double> z = TipHeights(v, 8.0);  // ~10 decay times: z.back() is the rest
  ASSERT_FALSE(z.empty());
  const double rest = z.back(), h = v("simulation.timestep_s");
  // Upward crossings of the rest height bound the cycles; a cycle's amplitude is its
  // largest distance below the rest.
  std::vector<size_t> up;
  for (size_t i = 1; i < z.size(); ++i)
    if (z[i - 1] < rest && z[i] >= rest) up.push_back(i);
  ASSERT_GE(up.size(), 8u);
  std::vector<double> amp;
  for (size_t c = 0; c + 1 < up.size(); ++c) {
    double a = 0;
    for (size_t i = up[c]; i < up[c + 1]; ++i) a = std::max(a, rest - z[i]);
    amp.push_back(a);
  }
  // From the third cycle (the second mode, damped several times harder, has died out) over
  // ten cycles, while the amplitude is still far above the rest's own error.
  const size_t c0 = 2, c1 = std::min<size_t>(12, amp.size() - 1);
  const double period = (up[c1] - up[c0]) * h / static_cast<double>(c1 - c0);
  const double delta = std::log(amp[c0] / amp[c1]) / static_cast<double>(c1 - c0);
  const double zeta = delta / std::sqrt(4 * M_PI * M_PI + delta * delta);
  const double omega = 2 * M_PI / period / std::sqrt(1 - zeta * zeta);
  const double expected = v("joint.bend_damping_nms_per_rad") /
                          v("joint.bend_stiffness_nm_per_rad") * omega / 2;
  EXPECT_NEAR(zeta, expected, 0.1 * expected) << "omega " << omega << " rad/s";
}

}  // namespace
}  // namespace gaitforge::generic
