// Paper 004's state-dependent joint parameters as effects on the continuum arm's bending
// joints (workers/effects: joint.softening, joint.damping_growth, joint.stiffening): each
// is the arm as it is at its nominal value and simulates at both ends of its range;
// softening moves the static bend to its closed form; damping growth and speed stiffening
// leave the static bend alone and change only the motion towards it.
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "gtest/gtest.h"
#include "robots/registry.h"
#include "workers/effects/effects.h"
#include "workers/models/generic/generic_world.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::generic {
namespace {

const robots::RobotDescriptor& Arm() { return robots::Robot("continuum_arm"); }

// The rods' forces (N) held from rest without gravity for `seconds`: every joint's first
// angle after each step.
struct ArmRun {
  bool ok = true;
  std::string reason;
  std::vector<double> angle{};  // j3.angle1 over time
  double tip_x = 0;
};

ArmRun Hold(const std::vector<double>& f, double seconds, const std::map<std::string, double>& set) {
  ParamValues v(Arm());
  EXPECT_TRUE(v.Set("simulation.gravity_m_per_s2", 0).ok());
  for (const auto& [name, value] : set) EXPECT_TRUE(v.Set(name, value).ok()) << name;
  auto w = GenericWorld::Build(Arm(), v, 0);
  ArmRun r;
  if (!w.ok()) return {false, std::string(w.status().message())};
  for (int i = 0; i < std::lround(seconds / (*w)->timestep()); ++i) {
    const auto out = (*w)->Step(f);
    if (!out.ok) return {false, out.reason};
    r.angle.push_back(*(*w)->Channel("j3.angle1"));
  }
  r.tip_x = *(*w)->Channel("tip.x");
  return r;
}

class ArmEffectsTest : public ::testing::Test {
 protected:
  void SetUp() override { sim::InitThread(); }
};

// Rod 2 alone (at 120 degrees) bends every joint about x by M_x = r f sin(120 deg).
const std::vector<double> kRod2 = {0, 0.4, 0};

TEST_F(ArmEffectsTest, EachIsTheArmAsItIsAtNominalAndSimulatesOverItsRange) {
  const ArmRun base = Hold(kRod2, 0.5, {});
  int applied = 0;
  for (const auto& e : effects::EffectCatalog()) {
    if (e.attaches != "bending_joints") continue;
    EXPECT_EQ(effects::WhyNotApplicable(e, Arm()), "") << e.id;
    ++applied;
    for (const auto& p : e.params) {
      EXPECT_EQ(Hold(kRod2, 0.5, {{p.name, p.nominal}}).angle, base.angle) << p.name;
      for (double value : {p.lo, p.hi}) {
        const ArmRun r = Hold(kRod2, 0.5, {{p.name, value}});
        EXPECT_TRUE(r.ok) << p.name << " = " << value << ": " << r.reason;
      }
    }
  }
  EXPECT_EQ(applied, 3);
  EXPECT_NE(effects::WhyNotApplicable(*effects::FindEffect("joint.softening"), robots::Robot("walker")), "");
}

// At rest each joint carries M = k psi / sqrt(1 + (s psi)^2), so psi = (M / k) / sqrt(1 -
// (s M / k)^2): the linear bend psi_0 = M / k grows by 1 / sqrt(1 - (s psi_0)^2).
TEST_F(ArmEffectsTest, SofteningBendsFurtherAsItsClosedFormSays) {
  const ParamValues v(Arm());
  const double m = v("rods.radius_m") * kRod2[1] * std::sin(2 * M_PI / 3);
  const double psi0 = m / v("joint.stiffness_x_nm_per_rad");
  const double s = 4;  // s psi_0 = 0.36: 7% further
  const ArmRun linear = Hold(kRod2, 8, {}), soft = Hold(kRod2, 8, {{"effect.joint_softening_per_rad", s}});
  ASSERT_TRUE(linear.ok && soft.ok);
  EXPECT_NEAR(std::fabs(linear.angle.back()), psi0, 0.02 * psi0);
  EXPECT_NEAR(std::fabs(soft.angle.back()), psi0 / std::sqrt(1 - s * s * psi0 * psi0), 0.02 * psi0);
}

// The rate-dependent effects leave the static bend as it is and damp or stiffen the way
// there: less overshoot of the final angle.
TEST_F(ArmEffectsTest, DampingGrowthAndStiffeningChangeOnlyTheMotion) {
  const ArmRun base = Hold(kRod2, 8, {});
  ASSERT_TRUE(base.ok);
  const auto overshoot = [](const ArmRun& r) {
    double peak = 0;
    for (double a : r.angle) peak = std::max(peak, std::fabs(a));
    return peak / std::fabs(r.angle.back()) - 1;
  };
  EXPECT_GT(overshoot(base), 0.05);  // the arm as it is rings
  for (const auto& [name, value] : std::map<std::string, double>{
           {"effect.joint_damping_growth_per_rad2", 100}, {"effect.joint_stiffening_s_per_rad", 5}}) {
    const ArmRun r = Hold(kRod2, 8, {{name, value}});
    ASSERT_TRUE(r.ok) << name << ": " << r.reason;
    EXPECT_NEAR(r.angle.back(), base.angle.back(), 1e-3 * std::fabs(base.angle.back())) << name;
    EXPECT_LT(overshoot(r), 0.9 * overshoot(base)) << name;
  }
}

}  // namespace
}  // namespace gaitforge::generic
