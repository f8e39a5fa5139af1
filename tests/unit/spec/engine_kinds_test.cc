// The engine registry: every engine a spec may name fills its defaults, validates, and
// makes an optimiser through its kind, with no switch on the name elsewhere.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "services/spec/engine_kinds.h"
#include "services/spec/spec_loader.h"
#include "services/spec/spec_validation.h"

namespace gaitforge::spec {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

v1::StudySpec Minimal(const std::string& engine,
                      const std::string& nsga2 =
                          "nsga2: {objectives: [{metric: f1, sense: minimize}, "
                          "{metric: f2, sense: maximize}]}\n") {
  auto loaded =
      ParseSpec("engine: " + engine +
                    "\npopulation: 12\ngenerations: 3\nobjective: {name: analytic.sphere}\n"
                    "bounds: [{name: a, lo: 0, hi: 1}, {name: b, lo: 0, hi: 1}]\n" +
                    (engine == "nsga2" ? nsga2 : ""),
                "s.yaml");
  EXPECT_TRUE(loaded.ok()) << loaded.status();
  ApplyDefaults(&loaded->spec);
  return loaded->spec;
}

TEST(EngineKinds, EveryKindValidatesAndMakesItsEngine) {
  std::set<std::string> names;
  for (const EngineKind& k : EngineKinds()) {
    EXPECT_TRUE(names.insert(k.name).second) << k.name;
    EXPECT_NE(v1::StudySpec::descriptor()->FindFieldByName(k.section), nullptr) << k.section;
    const v1::StudySpec spec = Minimal(k.name);
    EXPECT_TRUE(Validate(spec).empty()) << k.name << ": " << ValidationStatus(Validate(spec));
    auto engine = k.make(spec);
    ASSERT_TRUE(engine.ok()) << k.name << ": " << engine.status();
    EXPECT_FALSE((*engine)->Ask().empty()) << k.name;
    EXPECT_GE(k.evaluations_per_generation(spec, 12), 1);
  }
  EXPECT_EQ(EngineNames(), "ga, cmaes, sweep, nsga2");
}

TEST(EngineKinds, UnknownEnginesAndForeignSectionsAreRefused) {
  v1::StudySpec spec = Minimal("ga");
  spec.set_engine("pso");
  EXPECT_THAT(std::string(ValidationStatus(Validate(spec)).message()),
              HasSubstr("'pso' is not an engine; allowed: ga, cmaes, sweep, nsga2"));
  v1::StudySpec cma = Minimal("cmaes");
  cma.mutable_ga()->set_elite(2);
  EXPECT_THAT(std::string(ValidationStatus(Validate(cma)).message()),
              HasSubstr("field 'ga' is set but the engine is 'cmaes'"));
  // The GA leaves its elite out of the evaluations of a generation.
  EXPECT_EQ(FindEngineKind("ga")->evaluations_per_generation(Minimal("ga"), 12), 2);
}

TEST(EngineKinds, Nsga2NeedsObjectivesEachMetricOnceWithASense) {
  const auto message = [](const std::string& section) {
    return std::string(ValidationStatus(Validate(Minimal("nsga2", section))).message());
  };
  EXPECT_THAT(message("nsga2: {crossover_eta: 10}\n"),
              HasSubstr("field 'nsga2.objectives' has 0 entries; 2 to 8 metrics are needed"));
  EXPECT_THAT(message("nsga2: {objectives: [{metric: f1, sense: minimize}, "
                      "{metric: f1, sense: least}]}\n"),
              AllOf(HasSubstr("field 'nsga2.objectives[1].metric' 'f1' is named twice"),
                    HasSubstr("field 'nsga2.objectives[1].sense' = 'least' is not one of "
                              "maximize, minimize")));
  EXPECT_THAT(message("nsga2: {objectives: [{metric: f1, sense: minimize}, "
                      "{metric: f2, sense: maximize}], mutation_eta: -1}\n"),
              HasSubstr("field 'nsga2.mutation_eta' = -1 is out of range [0, 1000]"));
  // Defaults: Deb's 0.9 and 20, and one mutation per child on average.
  const v1::StudySpec spec = Minimal("nsga2");
  EXPECT_EQ(spec.nsga2().crossover_rate(), 0.9);
  EXPECT_EQ(spec.nsga2().mutation_rate(), 0.5);
}

TEST(EngineKinds, Nsga2ObjectivesComeFromTheMetricsHigherIsBetter) {
  const v1::StudySpec spec = Minimal("nsga2");
  v1::Evaluation e;
  e.set_valid(true);
  (*e.mutable_metrics())["f1"] = 2;
  (*e.mutable_metrics())["f2"] = 3;
  std::vector<double> out;
  ASSERT_TRUE(ObjectivesOf(spec, e, &out).ok());
  EXPECT_EQ(out, (std::vector<double>{-2, 3}));  // f1 is minimised
  e.mutable_metrics()->erase("f2");
  EXPECT_THAT(std::string(ObjectivesOf(spec, e, &out).message()),
              HasSubstr("metric 'f2' (nsga2.objectives[1]) was not reported"));
  e.set_valid(false);
  EXPECT_TRUE(ObjectivesOf(spec, e, &out).ok());
  EXPECT_TRUE(out.empty());
}

// A log gene: every engine is made over ln(x) and reports x; cmaes.mean0 and a sweep
// factor's values are written in the gene's units and mapped too.
TEST(EngineKinds, LogGenesAreSearchedByTheirLogarithmAndReportedInUnits) {
  for (const EngineKind& k : EngineKinds()) {
    v1::StudySpec spec = Minimal(k.name);
    spec.mutable_bounds(0)->set_lo(1e-5);
    spec.mutable_bounds(0)->set_log(true);
    ASSERT_TRUE(Validate(spec).empty()) << k.name << ": " << ValidationStatus(Validate(spec));
    auto engine = MakeEngine(spec);
    ASSERT_TRUE(engine.ok()) << k.name << ": " << engine.status();
    for (const auto& m : (*engine)->Ask()) {
      EXPECT_GE(m.genes[0], 1e-5) << k.name;
      EXPECT_LE(m.genes[0], 1.0) << k.name;
    }
  }
  v1::StudySpec cma = Minimal("cmaes");
  cma.mutable_bounds(0)->set_lo(1e-5);
  cma.mutable_bounds(0)->set_log(true);
  cma.mutable_cmaes()->add_mean0(1e-4);
  cma.mutable_cmaes()->add_mean0(0.5);
  cma.mutable_cmaes()->set_sigma0(1e-6);
  auto engine = MakeEngine(cma);
  ASSERT_TRUE(engine.ok()) << engine.status();
  EXPECT_NEAR((*engine)->Ask().at(0).genes[0], 1e-4, 1e-8);  // mean0 in units, not in ln
  EXPECT_NEAR((*engine)->Ask().at(0).genes[1], 0.5, 1e-4);
  // The sweep's grid over a log gene is geometric: 1e-5, 1e-4, ..., 1.
  v1::StudySpec sweep = Minimal("sweep");
  sweep.mutable_bounds(0)->set_lo(1e-5);
  sweep.mutable_bounds(0)->set_log(true);
  sweep.mutable_sweep()->clear_points_per_axis();
  sweep.mutable_sweep()->add_points_per_axis(6);
  sweep.mutable_sweep()->add_points_per_axis(1);
  auto grid = MakeEngine(sweep);
  ASSERT_TRUE(grid.ok()) << grid.status();
  std::set<double> decades;
  for (const auto& m : (*grid)->Ask()) decades.insert(std::round(std::log10(m.genes[0])));
  EXPECT_EQ(decades, (std::set<double>{-5, -4, -3, -2, -1, 0}));
}

TEST(EngineKinds, ALogGeneNeedsAPositiveRangeAndNoCircle) {
  v1::StudySpec spec = Minimal("cmaes");
  spec.mutable_bounds(1)->set_log(true);
  EXPECT_THAT(std::string(ValidationStatus(Validate(spec)).message()),
              HasSubstr("field 'bounds[1].log' needs lo > 0 (the gene is searched by its "
                        "logarithm); got lo = 0"));
  spec.mutable_bounds(1)->set_lo(0.1);
  spec.mutable_bounds(1)->set_circular(true);
  EXPECT_THAT(std::string(ValidationStatus(Validate(spec)).message()),
              HasSubstr("field 'bounds[1].log' and circular exclude each other"));
  // From a file the error names its line and column.
  auto loaded = ParseSpec("engine: cmaes\ngenerations: 3\nobjective: {name: analytic.sphere}\n"
                          "bounds:\n  - {name: a, lo: 0, hi: 1, log: true}\n",
                          "s.yaml");
  ASSERT_TRUE(loaded.ok()) << loaded.status();
  ApplyDefaults(&loaded->spec);
  EXPECT_THAT(std::string(ValidationStatus(Validate(loaded->spec), &*loaded).message()),
              HasSubstr("s.yaml:5:"));
}

}  // namespace
}  // namespace gaitforge::spec
