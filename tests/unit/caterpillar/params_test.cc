// caterpillar.yaml: the installed file loads, and each kind of mistake in a copy is reported
// with file, line, field, unit and allowed range.
#include <fstream>
#include <sstream>
#include <string>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "workers/models/caterpillar/caterpillar_params.h"

namespace gaitforge::caterpillar {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

std::string DefaultText() {
  std::ifstream in(DefaultCaterpillarParamsPath());
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The text with the first occurrence of `from` replaced by `to`.
std::string Edit(const std::string& from, const std::string& to) {
  std::string t = DefaultText();
  const size_t at = t.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return t.replace(at, from.size(), to);
}

// 1-based line of the first occurrence of `needle` in the default file.
int LineOf(const std::string& needle) {
  const std::string t = DefaultText();
  return 1 + static_cast<int>(std::count(t.begin(), t.begin() + t.find(needle), '\n'));
}

TEST(CaterpillarParams, InstalledFileHoldsTheCanonicalRobot) {
  const CaterpillarParams& p = DefaultCaterpillarParams();
  EXPECT_EQ(p.lumps.mass_kg, 0.030);
  EXPECT_EQ(p.lumps.spacing_m, 0.032);
  EXPECT_EQ(p.links.flexure.axial_n_per_m, 1040);
  EXPECT_EQ(p.links.segment.bending_nm_per_rad, 0.07);
  EXPECT_EQ(p.actuators.force_n, 8.8);
  EXPECT_EQ(p.actuators.return_spring_n_per_m, 63);
  EXPECT_NEAR(p.RestActuatorLength(), 0.051, 1e-12);
  EXPECT_TRUE(p.ground.infinite_friction);
  EXPECT_EQ(p.simulation.settle_cycles, 2);
}

TEST(CaterpillarParams, OutOfRangeValueNamesFileLineFieldUnitAndRange) {
  auto p = ParseCaterpillarParams(Edit("mass_kg: 0.030", "mass_kg: -2"), "copy.yaml");
  ASSERT_FALSE(p.ok());
  EXPECT_THAT(std::string(p.status().message()),
              AllOf(HasSubstr("copy.yaml:" + std::to_string(LineOf("mass_kg: 0.030"))),
                    HasSubstr("lumps.mass_kg = -2 kg"), HasSubstr("[0.001, 1] kg")));
}

TEST(CaterpillarParams, NonNumberIsRejected) {
  auto p = ParseCaterpillarParams(Edit("force_n: 8.8", "force_n: strong"), "copy.yaml");
  ASSERT_FALSE(p.ok());
  EXPECT_THAT(std::string(p.status().message()),
              AllOf(HasSubstr("actuators.force_n must be a number"), HasSubstr("[0, 100] N")));
}

TEST(CaterpillarParams, MissingFieldIsNamedWithUnitAndRange) {
  auto p = ParseCaterpillarParams(Edit("  timestep_s: 0.001", "  # gone"), "copy.yaml");
  ASSERT_FALSE(p.ok());
  EXPECT_THAT(std::string(p.status().message()),
              AllOf(HasSubstr("missing field simulation.timestep_s"), HasSubstr("[5e-05, 0.002] s")));
}

TEST(CaterpillarParams, UnknownFieldIsAnError) {
  auto p = ParseCaterpillarParams(Edit("mass_kg: 0.030", "mas_kg: 0.030"), "copy.yaml");
  ASSERT_FALSE(p.ok());
  EXPECT_THAT(std::string(p.status().message()), HasSubstr("unknown field lumps.mas_kg"));
}

TEST(CaterpillarParams, WholeNumberFieldsRejectFractions) {
  auto p = ParseCaterpillarParams(Edit("settle_cycles: 2", "settle_cycles: 2.5"), "copy.yaml");
  ASSERT_FALSE(p.ok());
  EXPECT_THAT(std::string(p.status().message()),
              AllOf(HasSubstr("simulation.settle_cycles = 2.5 cycles"), HasSubstr("whole number")));
}

TEST(CaterpillarParams, FrictionIsInfiniteOrACoefficient) {
  auto finite = ParseCaterpillarParams(Edit("friction: infinite", "friction: 0.8"), "copy.yaml");
  ASSERT_TRUE(finite.ok()) << finite.status();
  EXPECT_FALSE(finite->ground.infinite_friction);
  EXPECT_EQ(finite->ground.friction_coefficient, 0.8);
  auto bad = ParseCaterpillarParams(Edit("friction: infinite", "friction: sticky"), "copy.yaml");
  ASSERT_FALSE(bad.ok());
  EXPECT_THAT(std::string(bad.status().message()),
              AllOf(HasSubstr("ground.friction = sticky"), HasSubstr("\"infinite\"")));
}

TEST(CaterpillarParams, InconsistentStrokeIsRejected) {
  auto p = ParseCaterpillarParams(Edit("spacing_m: 0.032", "spacing_m: 0.050"), "copy.yaml");
  ASSERT_FALSE(p.ok());
  EXPECT_THAT(std::string(p.status().message()), HasSubstr("rest actuator length"));
}

TEST(CaterpillarParams, JsonTextIsAccepted) {
  const CaterpillarParams& d = DefaultCaterpillarParams();
  std::ostringstream j;
  j.precision(17);
  j << R"({"format": "gaitforge.caterpillar.v1",
    "lumps": {"mass_kg": 0.03, "size_x_m": 0.03, "size_y_m": 0.04, "size_z_m": 0.025,
              "spacing_m": 0.032},
    "links": {"flexure": {"axial_stiffness_n_per_m": 1040, "bending_stiffness_nm_per_rad": 0.12},
              "segment": {"axial_stiffness_n_per_m": 446, "bending_stiffness_nm_per_rad": 0.07},
              "axial_damping_ratio": 1, "bending_damping_ratio": 1},
    "actuators": {"force_n": 8.8, "return_spring_n_per_m": 63, "min_length_m": 0.051,
                  "max_length_m": 0.062, "rear_attach_x_m": -0.0095, "front_attach_x_m": 0.0095,
                  "top_attach_z_m": 0.0125, "bottom_attach_z_m": -0.008, "stop_erp": 0.8,
                  "stop_cfm": 1e-5, "overrun_tolerance_m": 0.002},
    "ground": {"friction": "infinite", "contact_erp": 0.2, "contact_cfm": 1e-5},
    "markers": {"offset_x_m": 0, "offset_z_m": 0.0125},
    "simulation": {"gravity_m_per_s2": 9.81, "timestep_s": 0.001, "settle_cycles": 2,
                   "measured_cycles": 1, "solver_erp": 0.2, "solver_cfm": 1e-10,
                   "max_speed_m_per_s": 20, "max_excursion_m": 5}})";
  auto p = ParseCaterpillarParams(j.str(), "inline.json");
  ASSERT_TRUE(p.ok()) << p.status();
  EXPECT_EQ(p->actuators.force_n, d.actuators.force_n);
  EXPECT_EQ(p->simulation.timestep_s, d.simulation.timestep_s);
}

TEST(CaterpillarParams, MissingFileIsNotFound) {
  auto p = LoadCaterpillarParams("/nonexistent/caterpillar.yaml");
  ASSERT_FALSE(p.ok());
  EXPECT_THAT(std::string(p.status().message()), HasSubstr("/nonexistent/caterpillar.yaml"));
}

}  // namespace
}  // namespace gaitforge::caterpillar
