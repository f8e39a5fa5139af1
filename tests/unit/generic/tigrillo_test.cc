// Paper 003's Tigrillo (robots/tigrillo/robot.yaml) on the generic builder: it stands on its
// four feet with its knees folding under its weight, a foot's contact depth lets it sink by
// that much (the paper's calibrated d), and its CPG walk runs as a gait.
#include <cmath>
#include <string>

#include "gtest/gtest.h"
#include "robots/registry.h"
#include "workers/models/generic/generic_gait.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::generic {
namespace {

const robots::RobotDescriptor& Tigrillo() { return robots::Robot("tigrillo"); }

class TigrilloTest : public ::testing::Test {
 protected:
  void SetUp() override { sim::InitThread(); }
  // The robot after `seconds` with its hips held at 0.
  static std::unique_ptr<GenericWorld> Rest(const ParamValues& v, double seconds) {
    auto w = GenericWorld::Build(Tigrillo(), v, 0);
    EXPECT_TRUE(w.ok()) << w.status();
    const int n = static_cast<int>(std::lround(seconds / (*w)->timestep()));
    for (int i = 0; i < n; ++i) EXPECT_TRUE((*w)->Step({0, 0, 0, 0}).ok) << "step " << i;
    return std::move(*w);
  }
};

TEST_F(TigrilloTest, StandsOnItsFourFeetWithItsKneesFoldingUnderItsWeight) {
  ParamValues v(Tigrillo());
  auto w = Rest(v, 2.0);
  EXPECT_LT(w->max_tilt(), 0.15);
  EXPECT_GE(w->ground_contacts(), 4);
  EXPECT_NEAR(w->total_mass(), 0.95, 1e-9);  // the paper's total, whatever the share
  for (const char* knee : {"knee_fl.angle", "knee_fr.angle", "knee_hl.angle", "knee_hr.angle"}) {
    const double a = *w->Channel(knee);
    EXPECT_GT(a, 0.01) << knee;  // folded from its rest
    EXPECT_LT(a, 1.5) << knee;   // and holding
  }
  // The stiffer hind springs of the paper's calibration fold the hind knees less.
  ParamValues stiff(Tigrillo());
  ASSERT_TRUE(stiff.Set("knee.hind_stiffness_nm_per_rad", 0.5397).ok());
  auto s = Rest(stiff, 2.0);
  EXPECT_LT(*s->Channel("knee_hl.angle"), *w->Channel("knee_hl.angle"));
}

TEST_F(TigrilloTest, AFootsContactDepthLetsItSinkThatMuch) {
  ParamValues shallow(Tigrillo());
  ParamValues deep(Tigrillo());
  for (ParamValues* v : {&shallow, &deep})
    for (const char* d : {"contact.front_depth_m", "contact.hind_depth_m"})
      ASSERT_TRUE(v->Set(d, v == &deep ? 0.005 : 0.0).ok());
  const double sink = Rest(shallow, 1.0)->CentreOfMass()[2] - Rest(deep, 1.0)->CentreOfMass()[2];
  EXPECT_NEAR(sink, 0.005, 0.0015);
}

TEST_F(TigrilloTest, ItsCpgWalkRunsAsAGait) {
  ParamValues v(Tigrillo());
  // f, amp_front, amp_hind, off_front, off_hind, lr (walk), fh, w
  const std::vector<double> walk = {1.0, 0.35, 0.35, 0.0, 0.0, 0.5, 0.25, 5.0};
  const GaitResult a = EvaluateGait(Tigrillo(), v, walk);
  ASSERT_TRUE(a.valid) << a.reason;
  EXPECT_NEAR(a.simulated_s, 12.0, 1e-9);  // 2 settling + 10 measured cycles at 1 Hz
  EXPECT_EQ(EvaluateGait(Tigrillo(), v, walk).distance_per_cycle_m, a.distance_per_cycle_m);
  std::vector<double> bound = walk;
  bound[5] = 0.0;
  const GaitResult b = EvaluateGait(Tigrillo(), v, bound);
  ASSERT_TRUE(b.valid) << b.reason;
  EXPECT_NE(b.distance_per_cycle_m, a.distance_per_cycle_m);
}

}  // namespace
}  // namespace gaitforge::generic
