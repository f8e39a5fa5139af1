// The spec of a validation study (services/spec/validation_spec.h): a sweep with one level
// per gait that the real validator accepts, a fresh ensemble, and the refusals.
#include "services/spec/validation_spec.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "services/spec/spec_loader.h"
#include "services/spec/spec_validation.h"

namespace gaitforge::spec {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

v1::StudySpec Study(bool robust) {
  const std::string text = std::string("name: robust-walk\nseed: 9\npopulation: 10\ngenerations: 2\n"
                                       "ga: {elite: 2}\nobjective:\n  name: caterpillar.distance\n"
                                       "  from_calibration: cal-1\n") +
                           (robust ? "  robust: {numerics: [standard], statistic: mean_minus_sd, "
                                     "k: 0.5}\n"
                                   : "");
  auto loaded = ParseSpec(text, "study.yaml");
  EXPECT_TRUE(loaded.ok()) << loaded.status();
  ApplyDefaults(&loaded->spec);
  return loaded->spec;
}

v1::Gait Gait(const v1::StudySpec& s, double u) {
  v1::Gait g;
  for (const auto& b : s.bounds()) g.add_genes(b.lo() + u * (b.hi() - b.lo()));
  return g;
}

v1::Validation Request(const std::string& id, const std::vector<v1::Gait>& gaits, int members = 0,
                       uint64_t seed = 0) {
  v1::Validation r;
  r.set_study_id(id);
  for (const auto& g : gaits) *r.add_gaits() = g;
  r.set_members(members);
  r.set_seed(seed);
  return r;
}

TEST(ValidationSpec, OneLevelPerGaitOverAFreshLargerEnsembleThatTheValidatorAccepts) {
  const v1::StudySpec study = Study(true);
  ASSERT_EQ(study.bounds_size(), 13);
  ASSERT_EQ(study.objective().robust().members(), 6);
  v1::Validation req = Request("robust-walk-1a", {Gait(study, 0.1), Gait(study, 0.5), Gait(study, 0.9)});
  auto v = ValidationSpec(study, req);
  ASSERT_TRUE(v.ok()) << v.status();
  EXPECT_EQ(v->name(), "robust-walk-validation");
  EXPECT_EQ(v->engine(), "sweep");
  EXPECT_EQ(v->objective().robust().members(), 24);  // four times the study's six
  EXPECT_EQ(v->objective().robust().seed(), 10u);    // the study's ensemble seed + 1
  EXPECT_EQ(v->objective().robust().k(), 0.5);       // the study's statistic
  EXPECT_TRUE(v->objective().from_calibration().empty());  // resolved once, when stored
  ASSERT_EQ(v->sweep().factors_size(), 1);
  ASSERT_EQ(v->sweep().factors(0).genes_size(), 13);
  EXPECT_EQ(v->sweep().factors(0).genes(4).values(1), req.gaits(1).genes(4));
  // The request, resolved, stays with the spec: which study, which gaits, members and seed.
  EXPECT_EQ(v->validate().study_id(), "robust-walk-1a");
  EXPECT_EQ(v->validate().gaits_size(), 3);
  EXPECT_EQ(v->validate().members(), 24);
  EXPECT_EQ(v->validate().seed(), 10u);
  v1::StudySpec checked = *v;
  ApplyDefaults(&checked);
  const auto errors = Validate(checked);
  ASSERT_TRUE(errors.empty()) << errors.front().path << ": " << errors.front().message;
  req.set_members(40);
  req.set_seed(77);
  v = ValidationSpec(study, req);
  ASSERT_TRUE(v.ok());
  EXPECT_EQ(v->objective().robust().members(), 40);
  EXPECT_EQ(v->objective().robust().seed(), 77u);
}

TEST(ValidationSpec, RefusesAStudyWithoutEnsembleBadGaitsAndTheStudysOwnSeed) {
  const v1::StudySpec study = Study(true);
  auto error = [&](const v1::StudySpec& s, const v1::Validation& r) {
    auto v = ValidationSpec(s, r);
    return v.ok() ? std::string("accepted") : std::string(v.status().message());
  };
  EXPECT_THAT(error(Study(false), Request("p-1", {Gait(study, 0.5)})),
              HasSubstr("study p-1 has no objective.robust"));
  EXPECT_THAT(error(study, Request("s-1", {})), HasSubstr("no gaits"));
  EXPECT_THAT(error(study, Request("s-1", {v1::Gait()})), HasSubstr("gait 1 has 0 genes; the study's space has 13"));
  v1::Gait far = Gait(study, 0.5);
  far.set_genes(12, 50);
  EXPECT_THAT(error(study, Request("s-1", {Gait(study, 0.5), far})),
              HasSubstr("gait 2: gene " + study.bounds(12).name() + " = 50 is outside its bounds"));
  EXPECT_THAT(error(study, Request("s-1", {Gait(study, 0.5)}, 0, 9)),
              HasSubstr("seed 9 is the study's own ensemble seed"));
  EXPECT_THAT(error(study, Request("s-1", {Gait(study, 0.5)}, 300)),
              HasSubstr("members 300 is out of range [1, 256]"));
}

TEST(ValidationSpec, GaitsFileOnePerLineWithCommentsAndErrorsNamingTheLine) {
  auto g = ParseGaits("# rank 0\n0.1 0.2 0.3\n\n0.4,0.5, 0.6  # the second\n", "g.txt", 3);
  ASSERT_TRUE(g.ok()) << g.status();
  ASSERT_EQ(g->size(), 2u);
  EXPECT_EQ((*g)[1][2], 0.6);
  EXPECT_THAT(std::string(ParseGaits("0.1 0.2 0.3\n0.1 x 0.3\n", "g.txt", 3).status().message()),
              HasSubstr("g.txt:2: 'x' is not a finite number"));
  EXPECT_THAT(std::string(ParseGaits("0.1 0.2\n", "g.txt", 3).status().message()),
              HasSubstr("g.txt:1: 2 genes; the study's space has 3"));
  EXPECT_THAT(std::string(ParseGaits("# nothing\n", "g.txt", 3).status().message()),
              HasSubstr("g.txt: no gaits"));
}

// A spec that only asks for a validation is checked for its own fields before the coordinator
// resolves it (the CLI's and the Python client's submit validate what they send).
TEST(ValidationSpec, AnUnresolvedRequestIsCheckedForItsOwnFieldsOnly) {
  auto errors = [](const std::string& text) {
    auto loaded = ParseSpec(text, "v.yaml");
    EXPECT_TRUE(loaded.ok()) << loaded.status();
    ApplyDefaults(&loaded->spec);
    std::string out;
    for (const auto& e : Validate(loaded->spec)) out += e.path + ": " + e.message + "\n";
    return out;
  };
  EXPECT_EQ(errors("validate: {study_id: walk-1, members: 24, top: 5}\n"), "");
  EXPECT_THAT(errors("validate: {members: 300, top: -1}\n"),
              AllOf(HasSubstr("validate.study_id: is required"),
                    HasSubstr("validate.members: = 300 is out of range [0, 256]"),
                    HasSubstr("validate.top: = -1 must be >= 0")));
}

}  // namespace
}  // namespace gaitforge::spec
