// objective.robust in a study spec: defaults filled, the word "standard" expanded to the
// robot's numeric variants, and every bad value refused naming its field, line and range.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "services/spec/spec_loader.h"
#include "services/spec/spec_validation.h"

namespace gaitforge::spec {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

absl::StatusOr<v1::StudySpec> Load(const std::string& robust,
                                   const std::string& objective = "caterpillar.distance") {
  const std::string text = "seed: 9\npopulation: 10\ngenerations: 2\nga: {elite: 2}\nobjective:\n  name: " +
                           objective + "\n  robust:\n" + robust;
  auto loaded = ParseSpec(text, "robust.yaml");
  if (!loaded.ok()) return loaded.status();
  ApplyDefaults(&loaded->spec);
  if (auto s = ValidationStatus(Validate(loaded->spec), &*loaded); !s.ok()) return s;
  return loaded->spec;
}

std::string Error(const std::string& robust, const std::string& objective = "caterpillar.distance") {
  auto s = Load(robust, objective);
  return s.ok() ? "accepted" : std::string(s.status().message());
}

TEST(RobustSpec, DefaultsAndTheStandardNumerics) {
  auto spec = Load("    numerics: [standard]\n    start_phases: 2\n");
  ASSERT_TRUE(spec.ok()) << spec.status();
  const auto& r = spec->objective().robust();
  EXPECT_EQ(r.numerics_size(), 6);  // the caterpillar has every standard variant
  EXPECT_EQ(r.numerics(0), "");
  EXPECT_EQ(r.numerics(1), "simulation.timestep_s=0.0005");
  EXPECT_EQ(r.members(), 12);  // one per variant and phase
  EXPECT_EQ(r.seed(), 9u);     // the study's
  EXPECT_EQ(r.statistic(), "mean");
  EXPECT_EQ(r.quantile(), 0.25);
  EXPECT_EQ(r.k(), 1);
}

TEST(RobustSpec, BadValuesNameTheirFieldAndRange) {
  EXPECT_THAT(Error("    members: 0\n"),
              AllOf(HasSubstr("robust.yaml:8:5: field 'objective.robust.members' = 0 is out of "
                              "range [1, 256]")));
  EXPECT_THAT(Error("    statistic: quantile\n    quantile: 1.5\n"),
              HasSubstr("field 'objective.robust.quantile' = 1.5 must lie in (0, 1)"));
  for (const char* q : {"0", "1", "-0.25"})  // the interval is open at both ends
    EXPECT_THAT(Error(std::string("    statistic: quantile\n    quantile: ") + q + "\n"),
                HasSubstr("must lie in (0, 1)")) << q;
  // A factor is checked through what it multiplies: 0.030 kg x 50 leaves [0.001, 1] kg.
  EXPECT_THAT(Error("    parameters:\n      - {name: scale.mass, lo: 0.5, hi: 50}\n"),
              AllOf(HasSubstr("field 'objective.robust.parameters[0].name'"),
                    HasSubstr("scale.mass = 50 makes lumps.mass_kg = 1.5 kg is outside")));
  EXPECT_EQ(Error("    parameters:\n      - {name: scale.mass, lo: 0.5, hi: 2}\n"), "accepted");
  EXPECT_THAT(Error("    statistic: median\n"),
              HasSubstr("'median' is not one of mean, quantile, mean_minus_sd"));
  EXPECT_THAT(Error("    parameters:\n      - {name: actuators.force_n, lo: 5, hi: 200}\n"),
              AllOf(HasSubstr("field 'objective.robust.parameters[0].name'"),
                    HasSubstr("actuators.force_n"), HasSubstr("[0, 100]")));
  EXPECT_THAT(Error("    parameters:\n      - {name: actuators.forse_n, lo: 5, hi: 9}\n"),
              HasSubstr("nearest: actuators.force_n"));
  EXPECT_THAT(Error("    parameters:\n      - {name: scale.mass, lo: 1.2, hi: 0.8}\n"),
              HasSubstr("needs finite lo <= hi"));
  EXPECT_THAT(Error("    numerics: [\"simulation.timestep_s=0.5\"]\n"),
              HasSubstr("field 'objective.robust.numerics[0]'"));
  EXPECT_THAT(Error("    numerics: [fast]\n"), HasSubstr("must be NAME=VALUE"));
  EXPECT_THAT(Error("    parameters:\n      - {name: ground.contact_cfm, lo: 0, hi: 1e-3, log: true}\n"),
              HasSubstr("field 'objective.robust.parameters[0].log' needs lo > 0"));
  EXPECT_THAT(Error("    parameters:\n      - {name: scale.mass, lo: 0.8, hi: 1.2, circular: true}\n"),
              HasSubstr("field 'objective.robust.parameters[0].circular'"));
  EXPECT_THAT(Error("    members: 2\n", "analytic.sphere"),
              HasSubstr("analytic.sphere takes no robust evaluation; objectives that do: "
                        "caterpillar.distance, robot.distance"));
}

TEST(RobustSpec, AValidEnsembleIsAccepted) {
  auto spec = Load(
      "    members: 8\n    numerics: [\"\", \"ground.contact_cfm=3e-5\"]\n"
      "    parameters:\n      - {name: scale.link_stiffness, lo: 0.8, hi: 1.25}\n"
      "      - {name: ground.contact_cfm, lo: 1e-6, hi: 1e-3, log: true}\n"
      "    statistic: mean_minus_sd\n    k: 0.5\n");
  ASSERT_TRUE(spec.ok()) << spec.status();
  EXPECT_EQ(spec->objective().robust().members(), 8);
  EXPECT_TRUE(spec->objective().robust().parameters(1).log());
}

// Joint samples: one value per parameter, each inside its range, the line of the bad one
// named; `sampling` is a from_calibration choice.
TEST(RobustSpec, SamplesAreCheckedValueByValue) {
  const std::string two =
      "    parameters:\n      - {name: scale.link_stiffness, lo: 0.8, hi: 1.25}\n"
      "      - {name: actuators.force_n, lo: 8, hi: 10}\n";
  auto spec = Load(two + "    samples:\n      - {values: [0.9, 9.5]}\n      - {values: [1.2, 8]}\n");
  ASSERT_TRUE(spec.ok()) << spec.status();
  EXPECT_EQ(spec->objective().robust().samples(1).values(0), 1.2);
  EXPECT_THAT(Error(two + "    samples:\n      - {values: [0.9]}\n"),
              HasSubstr("field 'objective.robust.samples[0].values' has 1 values for 2 parameters"));
  EXPECT_THAT(Error(two + "    samples:\n      - {values: [0.9, 9]}\n      - {values: [0.9, 11]}\n"),
              AllOf(HasSubstr(":13:"), HasSubstr("field 'objective.robust.samples[1].values[1]' = 11 "
                                                 "leaves actuators.force_n's range [8, 10]")));
  EXPECT_THAT(Error("    sampling: posterior\n"),
              HasSubstr("field 'objective.robust.sampling' 'posterior' is not one of box, fits"));
  EXPECT_THAT(Error("    sampling: fits\n"), HasSubstr("it needs objective.from_calibration"));
}

// The caterpillar's 13 genes with the period marked circular, or a phase over half a cycle.
std::string CircularError(bool mark_period, bool half_phase) {
  std::string text = "population: 10\ngenerations: 2\nga: {elite: 2}\n"
                     "objective: {name: caterpillar.distance}\nbounds:\n";
  for (const char* row : {"a", "d"})
    for (const char* a : {"T1", "T2", "T3", "B1", "B2", "B3"})
      text += std::string("  - {name: ") + row + "_" + a + ", lo: 0, hi: " +
              (half_phase && std::string(a) == "T1" && std::string(row) == "a" ? "0.5" : "1") +
              ", circular: true}\n";
  text += std::string("  - {name: T, lo: 0.2, hi: 2") + (mark_period ? ", circular: true" : "") + "}\n";
  auto loaded = ParseSpec(text, "circ.yaml");
  if (!loaded.ok()) return std::string(loaded.status().message());
  ApplyDefaults(&loaded->spec);
  auto s = ValidationStatus(Validate(loaded->spec), &*loaded);
  return s.ok() ? "accepted" : std::string(s.message());
}

TEST(CircularSpec, OnlyWholeCyclePhasesMayBeCircular) {
  EXPECT_EQ(CircularError(false, false), "accepted");
  EXPECT_THAT(CircularError(true, false),
              HasSubstr("field 'bounds[12].circular' 'T' is not a phase of robot caterpillar's "
                        "controller; only phase genes may be circular"));
  EXPECT_THAT(CircularError(false, true),
              HasSubstr("field 'bounds[0].circular' needs 'a_T1' to span one whole cycle"));
}

}  // namespace
}  // namespace gaitforge::spec
