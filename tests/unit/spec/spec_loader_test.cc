#include <gtest/gtest.h>

#include "services/spec/spec_loader.h"
#include "services/spec/spec_validation.h"
#include "tests/support/temp_dir.h"

namespace gaitforge::spec {
namespace {

absl::Status Check(const std::string& text) {
  auto loaded = ParseSpec(text, "s.yaml");
  if (!loaded.ok()) return loaded.status();
  ApplyDefaults(&loaded->spec);
  return ValidationStatus(Validate(loaded->spec), &*loaded);
}

const char* kGood =
    "name: t\nseed: 3\npopulation: 20\ngenerations: 4\nobjective:\n  name: analytic.sphere\n"
    "  params:\n    work_us: 5\n";

TEST(SpecLoader, AGoodSpecLoadsWithDefaults) {
  auto loaded = ParseSpec(kGood, "s.yaml");
  ASSERT_TRUE(loaded.ok()) << loaded.status();
  ApplyDefaults(&loaded->spec);
  EXPECT_TRUE(Validate(loaded->spec).empty());
  EXPECT_EQ(loaded->spec.engine(), "ga");
  EXPECT_EQ(loaded->spec.ga().elite(), 10);
  EXPECT_DOUBLE_EQ(loaded->spec.ga().mutation_rate(), 0.10);
  ASSERT_EQ(loaded->spec.bounds_size(), 13);  // the analytic default: a unit box
  EXPECT_EQ(loaded->spec.bounds(12).name(), "x13");
  EXPECT_DOUBLE_EQ(loaded->spec.bounds(12).lo(), 0);
  EXPECT_DOUBLE_EQ(loaded->spec.bounds(12).hi(), 1);
  EXPECT_DOUBLE_EQ(loaded->spec.objective().params().at("work_us"), 5);
}

TEST(SpecLoader, JsonIsAcceptedToo) {
  auto s = Check(R"({"seed": 1, "population": 12, "generations": 2,
                     "objective": {"name": "analytic.rastrigin"}})");
  EXPECT_TRUE(s.ok()) << s;
}

TEST(SpecLoader, UnknownFieldNamesLineAndKnownFields) {
  auto s = Check("seed: 1\npopulaton: 20\n");
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("s.yaml:2:1"), std::string::npos) << s;
  EXPECT_NE(s.message().find("unknown field 'populaton'"), std::string::npos) << s;
  EXPECT_NE(s.message().find("population"), std::string::npos) << s;
}

TEST(SpecLoader, OutOfRangeValuesNameFieldLineAndRange) {
  auto s = Check(std::string(kGood) + "ga:\n  mutation_rate: 1.5\n");
  EXPECT_NE(s.message().find("s.yaml:10:3: field 'ga.mutation_rate' = 1.5 is out of range [0, 1]"),
            std::string::npos)
      << s;
  s = Check("population: 1\ngenerations: 0\nobjective: {name: analytic.sphere}\n");
  EXPECT_NE(s.message().find("s.yaml:1:1: field 'population' = 1 is out of range [2, 100000]"),
            std::string::npos)
      << s;
  EXPECT_NE(s.message().find("field 'generations' = 0 is out of range [1, 100000]"),
            std::string::npos)
      << s;
  s = Check(std::string(kGood) + "bounds:\n  - {name: a, lo: 1, hi: 0}\n");
  EXPECT_NE(s.message().find("field 'bounds[0]' needs finite lo < hi"), std::string::npos) << s;
  s = Check("population: 20\ngenerations: 2\nobjective:\n  name: analytic.sphere\n  params:\n"
            "    work_us: -1\n    bogus: 2\n");
  EXPECT_NE(s.message().find("s.yaml:6:5: field 'objective.params.work_us' = -1 is out of range"),
            std::string::npos)
      << s;
  EXPECT_NE(s.message().find("'objective.params.bogus' is not a parameter"), std::string::npos)
      << s;
}

TEST(SpecLoader, NanAndWrongTypesAreRejected) {
  auto s = Check("population: 20\ngenerations: 2\nobjective: {name: analytic.sphere}\n"
                 "bounds:\n  - {name: a, lo: .nan, hi: 1}\n");
  EXPECT_NE(s.message().find("s.yaml:5:19: field 'bounds[0].lo': expected a finite number"),
            std::string::npos)
      << s;
  s = Check("population: many\n");
  EXPECT_NE(s.message().find("field 'population': expected an integer"), std::string::npos) << s;
  s = Check("seed: -4\n");
  EXPECT_NE(s.message().find("field 'seed': expected an integer in [0,"), std::string::npos) << s;
  s = Check("objective: [1, 2]\n");
  EXPECT_NE(s.message().find("expected a mapping of ObjectiveSpec fields"), std::string::npos)
      << s;
  s = Check("population: 20\ngenerations: 2\nobjective: {name: analytic.nope}\n");
  EXPECT_NE(s.message().find("'analytic.nope' is not a known objective; one of analytic.sphere"),
            std::string::npos)
      << s;
  s = Check("a: [unclosed\n");
  EXPECT_NE(s.message().find("not valid YAML/JSON"), std::string::npos) << s;
}

TEST(SpecLoader, EngineSectionsAndConstraintsAreValidated) {
  auto s = Check("engine: cmaes\npopulation: 0\ngenerations: 5\n"
                 "objective: {name: analytic.sphere}\ncmaes:\n  sigma0: 2\n  restarts: often\n");
  EXPECT_NE(s.message().find("s.yaml:6:3: field 'cmaes.sigma0' = 2 is out of range (0, 1]"),
            std::string::npos)
      << s;
  EXPECT_NE(s.message().find("field 'cmaes.restarts' 'often' is not one of none, ipop, bipop"),
            std::string::npos)
      << s;
  s = Check("engine: sweep\ngenerations: 5\nobjective: {name: analytic.sphere}\n"
            "sweep: {points_per_axis: [10]}\n");
  EXPECT_NE(s.message().find("make a grid of 1e+13 points; at most 1e7"), std::string::npos) << s;
  s = Check(
      "engine: sweep\ngenerations: 5\nobjective: {name: analytic.sphere}\n"
      "bounds: [{name: a, lo: 0, hi: 1}, {name: b, lo: 0, hi: 1}]\n"
      "sweep:\n  top_k: 0\n  factors:\n"
      "    - {name: gait, levels: [trot, slide, pace], genes: [{gene: a, values: [0.1, 2]}, {gene: "
      "c, values: [1]}]}\n"
      "    - {name: speed, genes: [{gene: a, values: [0.5]}]}\n");
  EXPECT_NE(s.message().find("field 'sweep.factors[0].levels' names 3 levels; its genes have 2"),
            std::string::npos)
      << s;
  EXPECT_NE(
      s.message().find(
          "field 'sweep.factors[0].genes[0].values[1]' = 2 is outside the gene's bounds [0, 1]"),
      std::string::npos)
      << s;
  EXPECT_NE(
      s.message().find("field 'sweep.factors[0].genes[1].gene' 'c' is not a gene of the bounds"),
      std::string::npos)
      << s;
  EXPECT_NE(s.message().find("field 'sweep.factors[1].genes[0].gene' 'a' is set by another factor"),
            std::string::npos)
      << s;
  s = Check("population: 20\ngenerations: 5\nobjective: {name: analytic.sphere}\n"
            "cmaes: {sigma0: 0.2}\nconstraints:\n  - {metric: loss, min: 3, max: 1}\n"
            "  - {max: 1}\n");
  EXPECT_NE(s.message().find("field 'cmaes' is set but the engine is 'ga'"), std::string::npos)
      << s;
  EXPECT_NE(s.message().find("field 'constraints[0]' needs min <= max"), std::string::npos) << s;
  EXPECT_NE(s.message().find("field 'constraints[1].metric' is required"), std::string::npos)
      << s;
}

TEST(SpecLoader, MissingFileIsNotFound) {
  auto s = LoadSpecFile("/no/such/spec.yaml");
  EXPECT_EQ(s.status().code(), absl::StatusCode::kNotFound);
  EXPECT_NE(s.status().message().find("/no/such/spec.yaml"), std::string::npos);
}

TEST(SpecLoader, AKeyWrittenTwiceNamesBothLines) {
  auto s = Check(std::string(kGood) + "population: 30\n");
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("s.yaml:9:1: field 'population': written twice, on lines 3 and 9; keep one"),
            std::string::npos)
      << s;
  s = Check("objective:\n  name: analytic.sphere\n  params: {work_us: 1, work_us: 2}\n");
  EXPECT_NE(s.message().find("s.yaml:3:24: field 'objective.params.work_us': written twice on line 3"),
            std::string::npos)
      << s;
}

TEST(SpecLoader, AnEmptyBoundsListIsAnErrorNotTheDefaultSpace) {
  auto s = Check(std::string(kGood) + "bounds: []\n");
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("s.yaml:9:1: field 'bounds' is an empty list; give at least one "
                             "gene, or leave 'bounds' out"),
            std::string::npos)
      << s;
}

TEST(SpecLoader, AnErrorThatFollowsFromAnotherIsNotReported) {
  auto s = Check("population: 0\ngenerations: 2\nobjective: {name: analytic.sphere}\n");
  EXPECT_NE(s.message().find("field 'population' = 0 is out of range [2, 100000]"),
            std::string::npos)
      << s;
  EXPECT_EQ(s.message().find("ga.elite"), std::string::npos) << s;
  s = Check("engine: cmaes\npopulation: 2\ngenerations: 2\nobjective: {name: analytic.sphere}\n"
            "cmaes: {max_evaluations: 1}\n");
  EXPECT_NE(s.message().find("field 'population' = 2 is out of range"), std::string::npos) << s;
  EXPECT_EQ(s.message().find("below one generation"), std::string::npos) << s;
}

TEST(SpecLoader, IntegersBeyondTheirTypeGetTheFieldsRange) {
  auto s = Check("population: 99999999999\ngenerations: 2\nobjective: {name: analytic.sphere}\n");
  EXPECT_NE(s.message().find("s.yaml:1:1: field 'population' = 99999999999 is out of range "
                             "[2, 100000]"),
            std::string::npos)
      << s;
  EXPECT_EQ(s.message().find("2147483647"), std::string::npos) << s;
  EXPECT_EQ(s.message().find("ga.elite"), std::string::npos) << s;
  s = Check(std::string(kGood) + "ga: {elite: -99999999999999999999999}\n");
  EXPECT_NE(s.message().find("field 'ga.elite' = -99999999999999999999999 is out of range [0, "
                             "population - 1 = 19]"),
            std::string::npos)
      << s;
}

TEST(SpecLoader, ADirectoryGivenAsASpecSaysSo) {
  gaitforge::testing::TempDir dir;
  auto s = LoadSpecFile(dir.path());
  EXPECT_EQ(s.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(s.status().message(),
            "'" + dir.path() + "' is a directory; give a spec file (.yaml or .json)");
}

TEST(SpecLoader, ExamplesInTheRepositoryAreValid) {
  for (const char* f :
       {"examples/analytic-ga.yaml", "examples/caterpillar-ga.yaml", "examples/analytic-cmaes.yaml",
        "examples/analytic-sweep.yaml", "examples/robot-ga.yaml",
        "examples/caterpillar-robust.yaml", "examples/go2-experiment.yaml",
        "examples/caterpillar-structure.yaml", "examples/caterpillar-from-calibration.yaml"}) {
    auto loaded = LoadSpecFile(std::string(GAITFORGE_SOURCE_DIR) + "/" + f);
    ASSERT_TRUE(loaded.ok()) << loaded.status();
    ApplyDefaults(&loaded->spec);
    EXPECT_TRUE(ValidationStatus(Validate(loaded->spec), &*loaded).ok()) << f;
  }
}

}  // namespace
}  // namespace gaitforge::spec
