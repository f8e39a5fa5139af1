// The effect catalog (workers/effects/effects.h): stable ids in order, each entry complete,
// each parameter in one effect only with a nominal value inside its range. What each effect
// does to a robot: tests/unit/generic (caterpillar_effects_test.cc, walker_test.cc).
#include <set>
#include <string>
#include <vector>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "robots/registry.h"
#include "workers/effects/effects.h"

namespace gaitforge::effects {
namespace {

TEST(EffectCatalog, HasTheStableIdsInOrder) {
  std::vector<std::string> ids;
  for (const auto& e : EffectCatalog()) ids.push_back(e.id);
  EXPECT_EQ(ids, (std::vector<std::string>{
                     "tether.constant", "tether.growing", "ground.slope", "friction.viscous",
                     "friction.anisotropic", "actuator.lag", "actuator.delay",
                     "actuator.force_scale", "actuator.deadband", "servo.deadband",
                     "contact.softness", "mass.offset", "stiffness.scale", "spring.softening",
                     "model.resolution", "damping.scale", "joint.softening",
                     "joint.damping_growth", "joint.stiffening", "contact.creep"}));
  for (const auto& e : EffectCatalog()) {
    EXPECT_EQ(FindEffect(e.id), &e);
    EXPECT_FALSE(e.name.empty() || e.meaning.empty() || e.where.empty() || e.experiment.empty())
        << e.id;
    EXPECT_FALSE(e.params.empty()) << e.id;
  }
  EXPECT_EQ(FindEffect("no.such"), nullptr);
}

TEST(EffectCatalog, EachParameterOnceWithItsNominalInRange) {
  std::set<std::string> seen;
  for (const auto& e : EffectCatalog()) {
    for (const auto& p : e.params) {
      EXPECT_TRUE(seen.insert(p.name).second) << p.name << " in two effects";
      EXPECT_LT(p.lo, p.hi) << p.name;
      EXPECT_GE(p.nominal, p.lo) << p.name;
      EXPECT_LE(p.nominal, p.hi) << p.name;
    }
  }
}

}  // namespace
}  // namespace gaitforge::effects

namespace gaitforge::effects {
namespace {

// Direction-dependent friction leaves a robot as it is at the robot's own coefficient: a
// finite-friction walker's fits start at 0.6 both ways; the no-slip caterpillar's at 0,
// which stands for its own ground.
TEST(EffectCatalog, DirectionalFrictionStartsAtTheRobotsOwnCoefficient) {
  const robots::RobotDescriptor* walker = robots::FindRobot("walker");
  const robots::RobotDescriptor* caterpillar = robots::FindRobot("caterpillar");
  ASSERT_TRUE(walker && caterpillar);
  auto w = FindEffect("friction.anisotropic", *walker);
  auto c = FindEffect("friction.anisotropic", *caterpillar);
  ASSERT_TRUE(w && c);
  ASSERT_EQ(w->params.size(), 2u);
  for (const auto& p : w->params) EXPECT_DOUBLE_EQ(p.nominal, walker->Value("ground.friction_coefficient"));
  for (const auto& p : c->params) EXPECT_DOUBLE_EQ(p.nominal, 0.0);
  EXPECT_DOUBLE_EQ(FindEffect("ground.slope", *walker)->params[0].nominal, 0.0);
}

// A robot's `ruled_out` entries name catalog effects, and those are not applicable to it,
// with the descriptor's reason; the walker carries its battery, so nothing tethers it.
TEST(EffectCatalog, RuledOutEffectsAreCatalogIdsAndNotApplicable) {
  for (const std::string& name : robots::RobotNames()) {
    const robots::RobotDescriptor& d = robots::Robot(name);
    for (const robots::RuledOut& r : d.ruled_out) {
      const EffectInfo* e = FindEffect(r.id);
      ASSERT_NE(e, nullptr) << name << ": " << r.id;
      EXPECT_THAT(WhyNotApplicable(*e, d), ::testing::HasSubstr(r.why)) << name;
    }
  }
  const robots::RobotDescriptor& walker = robots::Robot("walker");
  EXPECT_THAT(WhyNotApplicable(*FindEffect("tether.constant"), walker),
              ::testing::AllOf(::testing::HasSubstr("rules it out"), ::testing::HasSubstr("battery")));
  EXPECT_EQ(WhyNotApplicable(*FindEffect("ground.slope"), walker), "");
  EXPECT_EQ(WhyNotApplicable(*FindEffect("tether.constant"), robots::Robot("caterpillar")), "");
}

}  // namespace
}  // namespace gaitforge::effects
