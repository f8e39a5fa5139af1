// Spheres on the generic builder (shape: sphere; docs/robots.md), on a fixture that exists
// only as data (tests/fixtures/robots/balls/robot.yaml): a ball rests on the ground at its
// radius, and on a slope a ball with friction rolls (a = 5/7 g sin s, a solid sphere's
// inertia 2/5 m r^2 and its contact point at rest) while a frictionless one slides
// (a = g sin s).
#include <cmath>

#include "gtest/gtest.h"
#include "robots/descriptor_parser.h"
#include "tests/support/fixture_robot.h"
#include "workers/models/generic/generic_world.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::generic {
namespace {

const robots::RobotDescriptor& Balls() { return testing::FixtureRobot("balls"); }

class SphereTest : public ::testing::Test {
 protected:
  void SetUp() override { sim::InitThread(); }
};

TEST_F(SphereTest, ABallRestsOnTheGroundAtItsRadius) {
  ParamValues v(Balls());
  auto w = GenericWorld::Build(Balls(), v, 0);
  ASSERT_TRUE(w.ok()) << w.status();
  for (int i = 0; i < 2000; ++i) ASSERT_TRUE((*w)->Step({}).ok);  // 1 s
  EXPECT_NEAR(*(*w)->Channel("rolling_c.z"), v("ball.radius_m"), 2e-4);
  EXPECT_NEAR(*(*w)->Channel("rolling_c.x"), 0, 1e-9);
  EXPECT_EQ((*w)->ground_contacts(), 2);
}

TEST_F(SphereTest, OnASlopeAFrictionBallRollsAndAFrictionlessOneSlides) {
  ParamValues v(Balls());
  const double s = 0.1, t = 0.5;
  ASSERT_TRUE(v.Set("effect.slope_rad", s).ok());
  auto w = GenericWorld::Build(Balls(), v, 0);
  ASSERT_TRUE(w.ok()) << w.status();
  const int steps = static_cast<int>(std::lround(t / (*w)->timestep()));
  for (int i = 0; i < steps; ++i) ASSERT_TRUE((*w)->Step({}).ok);
  // + uphill along +x: both move towards -x.
  const double g = v("simulation.gravity_m_per_s2"), slide = 0.5 * g * std::sin(s) * t * t;
  EXPECT_NEAR(-*(*w)->Channel("sliding_c.x"), slide, 0.01 * slide);
  EXPECT_NEAR(-*(*w)->Channel("rolling_c.x"), 5.0 / 7.0 * slide, 0.01 * slide);
}

}  // namespace
}  // namespace gaitforge::generic
