// The generic ODE builder on a robot that exists only as a test fixture
// (tests/fixtures/robots/twobox/robot.yaml): it rests, its servo tracks within its speed
// limit, its gaits are deterministic and travel, and bad input is a reason, not a crash.
#include <cmath>
#include <string>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "robots/descriptor_parser.h"
#include "tests/support/fixture_robot.h"
#include "workers/models/generic/generic_gait.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::generic {
namespace {

using ::testing::HasSubstr;

const robots::RobotDescriptor& TwoBox() { return testing::FixtureRobot("twobox"); }

class GenericWorldTest : public ::testing::Test {
 protected:
  void SetUp() override { sim::InitThread(); }
};

TEST_F(GenericWorldTest, TheFixtureRestsOnTheGround) {
  ParamValues v(TwoBox());
  auto w = GenericWorld::Build(TwoBox(), v, 0);
  ASSERT_TRUE(w.ok()) << w.status();
  const auto start = (*w)->CentreOfMass();
  for (int i = 0; i < 500; ++i) ASSERT_TRUE((*w)->Step({0.0}).ok);
  const auto end = (*w)->CentreOfMass();
  EXPECT_NEAR(end[0], start[0], 1e-4);
  EXPECT_NEAR(end[2], 0.015, 1e-4);  // half the height above the ground
  EXPECT_GT((*w)->ground_contacts(), 0);
  EXPECT_NEAR(*(*w)->Channel("hinge.angle"), 0, 1e-3);
  EXPECT_NEAR(*(*w)->Channel("nose.z"), 0.03, 1e-3);
  EXPECT_FALSE((*w)->Channel("elbow.angle").ok());
}

TEST_F(GenericWorldTest, TheServoTracksWithinItsSpeedLimit) {
  ParamValues v(TwoBox());
  ASSERT_TRUE(v.Set("simulation.gravity_m_per_s2", 0).ok());  // no load on the servo
  ASSERT_TRUE(v.Set("servo.lag_s", 0).ok());
  auto w = GenericWorld::Build(TwoBox(), v, 0);
  ASSERT_TRUE(w.ok()) << w.status();
  // 20 ms at the 6 rad/s limit: at most 0.12 rad of relative rotation.
  for (int i = 0; i < 20; ++i) ASSERT_TRUE((*w)->Step({0.5}).ok);
  EXPECT_LE(std::fabs((*w)->JointAngle(0)), 0.12 + 1e-6);
  EXPECT_GT(std::fabs((*w)->JointAngle(0)), 0.05);
  for (int i = 0; i < 1000; ++i) ASSERT_TRUE((*w)->Step({0.5}).ok);
  EXPECT_NEAR((*w)->JointAngle(0), 0.5, 0.02);
}

TEST_F(GenericWorldTest, AGaitIsDeterministicAndTravels) {
  ParamValues v(TwoBox());
  const std::vector<double> genes = {2.0, 0.6, 0.2, 0.25};  // f, amp, off, phase
  const GaitResult a = EvaluateGait(TwoBox(), v, genes);
  const GaitResult b = EvaluateGait(TwoBox(), v, genes);
  ASSERT_TRUE(a.valid) << a.reason;
  EXPECT_EQ(a.distance_per_cycle_m, b.distance_per_cycle_m);  // bit for bit
  EXPECT_GT(std::fabs(a.distance_per_cycle_m), 1e-5);
  EXPECT_NEAR(a.simulated_s, 3 * 0.5, 1e-9);  // 1 settling + 2 measured cycles of 0.5 s
  // Another gait travels another distance: the genes reach the robot.
  const GaitResult c = EvaluateGait(TwoBox(), v, {2.0, 0.6, -0.2, 0.25});
  ASSERT_TRUE(c.valid) << c.reason;
  EXPECT_NE(c.distance_per_cycle_m, a.distance_per_cycle_m);
}

TEST_F(GenericWorldTest, BadInputIsAReasonNotACrash) {
  ParamValues v(TwoBox());
  const GaitResult wrong = EvaluateGait(TwoBox(), v, {2.0, 0.6});
  EXPECT_FALSE(wrong.valid);
  EXPECT_THAT(wrong.reason, HasSubstr("takes 4 genes, got 2"));
  EXPECT_THAT(std::string(v.Set("rear.mass_kg", -1).message()),
              HasSubstr("rear.mass_kg = -1 kg is outside [0.01, 2] kg"));
  EXPECT_EQ(v.Set("rear.mas_kg", 1).code(), absl::StatusCode::kNotFound);
}

}  // namespace
}  // namespace gaitforge::generic

namespace gaitforge::generic {
namespace {
// Two gaits of a GA run whose steps once ended in ODE's "LCP internal error, s <= 0" when
// every corner of a box on the ground carried friction rows.
TEST_F(GenericWorldTest, GaitsThatOnceBrokeTheSolverRunThrough) {
  ParamValues v(TwoBox());
  for (auto genes : std::vector<std::vector<double>>{
           {1.3144351052245153, 0.68038351904409999, 0.23567323925262318, 0.50517718664047229},
           {1.8949126434079326, 0.36331082255003094, 0.14127659686152216, 0.6853918893717541}}) {
    GaitOptions o;
    o.measured_cycles = 4;
    const GaitResult r = EvaluateGait(TwoBox(), v, genes, o);
    EXPECT_TRUE(r.valid) << r.reason;
  }
}
}  // namespace
}  // namespace gaitforge::generic
