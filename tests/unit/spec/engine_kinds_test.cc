// The engine registry: every engine a spec may name fills its defaults, validates, and
// makes an optimiser through its kind, with no switch on the name elsewhere.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <set>

#include "services/spec/engine_kinds.h"
#include "services/spec/spec_loader.h"
#include "services/spec/spec_validation.h"

namespace gaitforge::spec {
namespace {

using ::testing::HasSubstr;

v1::StudySpec Minimal(const std::string& engine) {
  auto loaded = ParseSpec("engine: " + engine +
                              "\npopulation: 12\ngenerations: 3\nobjective: {name: analytic.sphere}\n"
                              "bounds: [{name: a, lo: 0, hi: 1}, {name: b, lo: 0, hi: 1}]\n",
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
  EXPECT_EQ(EngineNames(), "ga, cmaes, sweep");
}

TEST(EngineKinds, UnknownEnginesAndForeignSectionsAreRefused) {
  v1::StudySpec spec = Minimal("ga");
  spec.set_engine("pso");
  EXPECT_THAT(std::string(ValidationStatus(Validate(spec)).message()),
              HasSubstr("'pso' is not an engine; allowed: ga, cmaes, sweep"));
  v1::StudySpec cma = Minimal("cmaes");
  cma.mutable_ga()->set_elite(2);
  EXPECT_THAT(std::string(ValidationStatus(Validate(cma)).message()),
              HasSubstr("field 'ga' is set but the engine is 'cmaes'"));
  // The GA leaves its elite out of the evaluations of a generation.
  EXPECT_EQ(FindEngineKind("ga")->evaluations_per_generation(Minimal("ga"), 12), 2);
}

}  // namespace
}  // namespace gaitforge::spec
