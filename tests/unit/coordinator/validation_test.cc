// A validation study resolved by the coordinator (services/coordinator/validation.h) against a
// real SQLite store: the robust study's valid hall-of-fame gaits become the sweep's levels,
// and what cannot be validated is refused with its reason and code.
#include "services/coordinator/validation.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "services/spec/spec_loader.h"
#include "services/spec/spec_validation.h"
#include "storage/study_store.h"
#include "tests/support/temp_dir.h"

namespace gaitforge::coordinator {
namespace {

using ::testing::HasSubstr;

const SpreadFn NoSpread = [](const std::string&, int) { return std::vector<double>{}; };

v1::StudySpec Robust(bool robust) {
  auto loaded = spec::ParseSpec(std::string("name: walk\nseed: 9\npopulation: 10\ngenerations: 2\n"
                                            "objective:\n  name: caterpillar.distance\n") +
                                    (robust ? "  robust: {numerics: [standard]}\n" : ""),
                                "s.yaml");
  EXPECT_TRUE(loaded.ok()) << loaded.status();
  spec::ApplyDefaults(&loaded->spec);
  return loaded->spec;
}

storage::HofRecord Entry(int rank, double u, bool valid) {
  storage::HofRecord h;
  h.rank = rank;
  h.genes.assign(12, u);
  h.genes.push_back(0.5);  // the period
  h.valid = valid;
  return h;
}

// A store holding study `id` (robust or not) whose hall of fame is `hof`.
std::unique_ptr<storage::StudyStore> Store(testing::TempDir& dir, const std::string& id, bool robust,
                                           const std::vector<storage::HofRecord>& hof) {
  auto store = storage::OpenSqliteStore(dir.File(id + ".db"));
  EXPECT_TRUE(store.ok()) << store.status();
  storage::StudyRecord study;
  study.study_id = id;
  study.name = "walk";
  study.spec = Robust(robust).SerializeAsString();
  study.state = "running";
  EXPECT_TRUE((*store)->CreateStudy(study).get().ok());
  storage::GenerationRecord gen;
  gen.study_id = id;
  gen.hall_of_fame = hof;
  gen.study_state = "completed";
  EXPECT_TRUE((*store)->CommitGeneration(gen).get().ok());
  return std::move(*store);
}

v1::StudySpec Request(const std::string& id, int top = 0) {
  v1::StudySpec s;
  s.mutable_validate()->set_study_id(id);
  s.mutable_validate()->set_top(top);
  return s;
}

TEST(Validation, TheStudysValidGaitsBecomeTheLevelsOfAFreshEnsemble) {
  testing::TempDir dir;
  auto store = Store(dir, "walk-1", true, {Entry(0, 0.1, true), Entry(1, 0.2, false), Entry(2, 0.3, true)});
  v1::StudySpec none;
  EXPECT_TRUE(ResolveValidation(*store, NoSpread, &none).ok());  // no validate: untouched
  EXPECT_EQ(none.engine(), "");
  v1::StudySpec s = Request("walk-1");
  ASSERT_TRUE(ResolveValidation(*store, NoSpread, &s).ok());
  EXPECT_EQ(s.name(), "walk-validation");
  EXPECT_EQ(s.engine(), "sweep");
  ASSERT_EQ(s.validate().gaits_size(), 2);  // the invalid entry is left out
  EXPECT_EQ(s.validate().gaits(1).genes(0), 0.3);
  EXPECT_EQ(s.sweep().factors(0).genes(0).values(1), 0.3);
  EXPECT_EQ(s.objective().robust().members(), 24);
  EXPECT_EQ(s.objective().robust().seed(), 10u);
  spec::ApplyDefaults(&s);
  EXPECT_TRUE(spec::Validate(s).empty());
  v1::StudySpec first = Request("walk-1", 1);
  ASSERT_TRUE(ResolveValidation(*store, NoSpread, &first).ok());
  EXPECT_EQ(first.validate().gaits_size(), 1);
  // A stored validation study submitted again is left as it is, and valid.
  v1::StudySpec again = s;
  ASSERT_TRUE(ResolveValidation(*store, NoSpread, &again).ok());
  EXPECT_EQ(again.SerializeAsString(), s.SerializeAsString());
}

TEST(Validation, RefusesAnUnknownStudyAnOwnObjectiveNoEnsembleAndNoValidGait) {
  testing::TempDir dir;
  auto store = Store(dir, "walk-1", true, {Entry(0, 0.1, true)});
  v1::StudySpec unknown = Request("walk-2");
  EXPECT_EQ(ResolveValidation(*store, NoSpread, &unknown).code(), absl::StatusCode::kNotFound);
  v1::StudySpec own = Request("walk-1");
  own.mutable_objective()->set_name("caterpillar.distance");
  auto s = ResolveValidation(*store, NoSpread, &own);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(s.message(), HasSubstr("takes its objective from the study it validates"));
  v1::StudySpec calibrated = Request("walk-1");
  calibrated.mutable_objective()->set_from_calibration("cal-1");
  EXPECT_THAT(ResolveValidation(*store, NoSpread, &calibrated).message(), HasSubstr("leave 'objective' out"));
  v1::StudySpec both = Request("walk-1", 2);
  *both.mutable_validate()->add_gaits() = v1::Gait();
  EXPECT_THAT(ResolveValidation(*store, NoSpread, &both).message(), HasSubstr("with gaits given"));
  // Without an ensemble the study is refused for that, whatever its hall of fame holds.
  auto plain = Store(dir, "paper-1", false, {Entry(0, 0.1, false)});
  v1::StudySpec p = Request("paper-1");
  EXPECT_THAT(ResolveValidation(*plain, NoSpread, &p).message(), HasSubstr("has no objective.robust"));
  auto failed = Store(dir, "bad-1", true, {Entry(0, 0.1, false)});
  v1::StudySpec b = Request("bad-1");
  s = ResolveValidation(*failed, NoSpread, &b);
  EXPECT_EQ(s.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_THAT(s.message(), HasSubstr("hall of fame holds no valid gait"));
}

}  // namespace
}  // namespace gaitforge::coordinator
