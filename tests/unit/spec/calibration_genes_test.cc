// A calibration's genes must be the robot's calibratable parameters: a misspelt name is
// refused when the spec is validated, with the nearest valid names and the line it is on
// (before, the study "completed" with every member invalid).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "services/spec/spec_loader.h"
#include "services/spec/spec_validation.h"

namespace gaitforge::spec {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

absl::Status Check(const std::string& bound_name) {
  const std::string text =
      "engine: cmaes\ngenerations: 3\nobjective:\n  name: caterpillar.calibration\n"
      "  recordings: [walk.csv]\nbounds:\n  - {name: actuators.force_n, lo: 4, hi: 12}\n"
      "  - {name: " + bound_name + ", lo: 0.5, hi: 2}\n";
  auto loaded = ParseSpec(text, "calib.yaml");
  if (!loaded.ok()) return loaded.status();
  ApplyDefaults(&loaded->spec);
  return ValidationStatus(Validate(loaded->spec), &*loaded);
}

TEST(CalibrationGenes, AMisspeltParameterIsRefusedWithTheNearestNames) {
  const absl::Status s = Check("scale.link_stifness");
  ASSERT_FALSE(s.ok());
  EXPECT_THAT(std::string(s.message()),
              AllOf(HasSubstr("calib.yaml:8:"), HasSubstr("field 'bounds[1].name'"),
                    HasSubstr("'scale.link_stifness' is not a calibratable parameter of the "
                              "caterpillar"),
                    HasSubstr("nearest: scale.link_stiffness")));
}

TEST(CalibrationGenes, AParameterThatIsNotCalibratableIsRefused) {
  // lumps.size_x_m is a parameter of the robot, but not one a calibration may set.
  EXPECT_THAT(std::string(Check("lumps.size_x_m").message()),
              HasSubstr("'lumps.size_x_m' is not a calibratable parameter"));
}

TEST(CalibrationGenes, ParametersScalesAndNuisanceAreAccepted) {
  for (const char* name : {"scale.link_stiffness", "effect.tether_force_n",
                           "ground.friction_coefficient", "nuisance.time_offset_s"}) {
    EXPECT_TRUE(Check(name).ok()) << name << ": " << Check(name);
  }
}

}  // namespace
}  // namespace gaitforge::spec
