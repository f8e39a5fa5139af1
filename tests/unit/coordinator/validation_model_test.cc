// A validation predicted by another calibration's model (services/coordinator/
// validation_model.h): the calibration's values and ranges replace the study's for the same
// names, the rest of the study's objective stays, and what cannot be re-based is refused.
#include "services/coordinator/validation_model.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "services/coordinator/validation.h"
#include "services/spec/spec_validation.h"
#include "tests/unit/coordinator/calibration_fixture.h"

namespace gaitforge::coordinator {
namespace {

using ::testing::HasSubstr;

const SpreadFn kSpread = [](const std::string&, int) {
  return std::vector<double>{0.1, 0.05, 0.001};
};

// A store holding calibration cal-2, completed, whose best fit is force 9, stiffness 1.2.
std::unique_ptr<storage::StudyStore> StoreWithFit(testing::TempDir& dir) {
  auto store = StoreWithCalibration(dir, "cal-2", "running");
  if (store == nullptr) return nullptr;
  storage::GenerationRecord gen;
  gen.study_id = "cal-2";
  storage::HofRecord best;
  best.genes = {9.0, 1.2, 0.01};
  best.valid = true;
  best.fitness = -0.5;
  gen.hall_of_fame = {best};
  gen.study_state = "completed";
  EXPECT_TRUE(store->CommitGeneration(gen).get().ok());
  EXPECT_TRUE(store->SetStudyState("cal-2", "completed", "").get().ok());
  return store;
}

// A robust gait study as a first calibration resolved it (force 9.5, stiffness 1), with an
// item and a range of the user's own.
v1::StudySpec FirstRound() {
  v1::StudySpec g;
  g.set_name("walk");
  g.set_seed(9);
  g.set_population(20);
  g.set_generations(2);
  auto* o = g.mutable_objective();
  o->set_name("caterpillar.distance");
  o->set_from_calibration("cal-1");
  (*o->mutable_options())["set"] = "actuators.force_n=9.5,scale.link_stiffness=1,effect.slope_rad=0.05";
  (*o->mutable_params())["timestep_ms"] = 0.5;
  auto* r = o->mutable_robust();
  r->set_members(6);
  for (const auto& [name, lo, hi] : std::vector<std::tuple<std::string, double, double>>{
           {"actuators.force_n", 9.3, 9.7}, {"scale.link_stiffness", 0.9, 1.1}, {"scale.mass", 0.9, 1.1}}) {
    auto* p = r->add_parameters();
    p->set_name(name);
    p->set_lo(lo);
    p->set_hi(hi);
  }
  spec::ApplyDefaults(&g);
  return g;
}

TEST(ValidationModel, MergeSetsKeepsTheFirstsItemsAndAddsTheOthers) {
  EXPECT_EQ(MergeSets("a=1,b=2", "b=3, c=4"), "a=1,b=2,c=4");
  EXPECT_EQ(MergeSets("", "c=4"), "c=4");
  EXPECT_EQ(MergeSets("a=1", ""), "a=1");
}

TEST(ValidationModel, TheCalibrationsValuesAndRangesReplaceTheStudysForTheSameNames) {
  testing::TempDir dir;
  auto store = StoreWithFit(dir);
  ASSERT_NE(store, nullptr);
  v1::StudySpec g = FirstRound();
  ASSERT_TRUE(RebaseOnCalibration(*store, kSpread, "cal-2", &g).ok());
  const auto& o = g.objective();
  EXPECT_EQ(o.options().at("set"), "actuators.force_n=9,scale.link_stiffness=1.2,effect.slope_rad=0.05");
  EXPECT_EQ(o.params().at("timestep_ms"), 0.5);
  EXPECT_EQ(o.robust().members(), 6);
  const auto& p = o.robust().parameters();
  ASSERT_EQ(p.size(), 3);
  EXPECT_EQ(p[0].name(), "actuators.force_n");
  EXPECT_NEAR(p[0].lo(), 8.8, 1e-12);
  EXPECT_NEAR(p[0].hi(), 9.2, 1e-12);
  EXPECT_NEAR(p[1].lo(), 1.1, 1e-12);
  EXPECT_EQ(p[2].name(), "scale.mass");  // the study's own, which cal-2 does not fit
  EXPECT_EQ(p[2].lo(), 0.9);
  for (const auto& e : spec::Validate(g)) ADD_FAILURE() << e.path << ": " << e.message;
}

// Through the coordinator's resolution: the validation study of walk-1's gaits carries
// cal-2's model and says where it came from.
TEST(ValidationModel, AValidationFromACalibrationIsASweepOnItsModel) {
  testing::TempDir dir;
  auto store = StoreWithFit(dir);
  ASSERT_NE(store, nullptr);
  storage::StudyRecord study;
  study.study_id = "walk-1";
  study.name = "walk";
  study.spec = FirstRound().SerializeAsString();
  study.state = "completed";
  ASSERT_TRUE(store->CreateStudy(study).get().ok());
  v1::StudySpec request;
  request.mutable_validate()->set_study_id("walk-1");
  request.mutable_validate()->set_from_calibration("cal-2");
  const std::vector<double> gait(13, 0.5);
  request.mutable_validate()->add_gaits()->mutable_genes()->Add(gait.begin(), gait.end());
  ASSERT_TRUE(ResolveValidation(*store, kSpread, &request).ok());
  EXPECT_EQ(request.engine(), "sweep");
  EXPECT_EQ(request.validate().from_calibration(), "cal-2");
  EXPECT_THAT(request.objective().options().at("set"), HasSubstr("actuators.force_n=9,"));
  EXPECT_TRUE(request.objective().from_calibration().empty());  // resolved: not again
  spec::ApplyDefaults(&request);
  for (const auto& e : spec::Validate(request)) ADD_FAILURE() << e.path << ": " << e.message;
}

TEST(ValidationModel, RefusesOwnSamplesAnUnknownCalibrationAndAnotherRobot) {
  testing::TempDir dir;
  auto store = StoreWithFit(dir);
  ASSERT_NE(store, nullptr);
  v1::StudySpec sampled = FirstRound();
  const std::vector<double> sample = {9.5, 1.0, 1.0};
  sampled.mutable_objective()->mutable_robust()->add_samples()->mutable_values()->Add(
      sample.begin(), sample.end());
  auto own = RebaseOnCalibration(*store, kSpread, "cal-2", &sampled);
  EXPECT_EQ(own.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(own.message(), HasSubstr("validate.from_calibration: the study's ensemble lists joint samples"));
  v1::StudySpec g = FirstRound();
  auto unknown = RebaseOnCalibration(*store, kSpread, "cal-9", &g);
  EXPECT_EQ(unknown.code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(unknown.message(), "validate.from_calibration: no study with id 'cal-9'");
  v1::StudySpec walker = FirstRound();
  walker.mutable_objective()->set_name("robot.distance");
  walker.mutable_objective()->set_robot("walker");
  auto other = RebaseOnCalibration(*store, kSpread, "cal-2", &walker);
  EXPECT_EQ(other.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(other.message(), HasSubstr("gait objective is 'caterpillar.distance', not 'robot.distance'"));
  EXPECT_EQ(walker.objective().options().at("set"), FirstRound().objective().options().at("set"));
}

}  // namespace
}  // namespace gaitforge::coordinator
