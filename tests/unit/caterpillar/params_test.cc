// The caterpillar's descriptor (robots/caterpillar/robot.yaml): the built-in one gives the
// canonical model, and each kind of mistake in a copy is reported with file, line, field,
// unit and allowed range.
#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>

#include <yaml-cpp/yaml.h>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "robots/registry.h"
#include "workers/models/caterpillar/caterpillar_params.h"

namespace gaitforge::caterpillar {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

std::string DefaultText() { return std::string(robots::BuiltinText("caterpillar")); }

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
  auto p = ParseCaterpillarParams(Edit("value: 0.030, range: [0.001, 1]",
                                       "value: -2, range: [0.001, 1]"), "copy.yaml");
  ASSERT_FALSE(p.ok());
  EXPECT_THAT(std::string(p.status().message()),
              AllOf(HasSubstr("copy.yaml:" + std::to_string(LineOf("mass_kg:")) + ":"),
                    HasSubstr("lumps.mass_kg = -2 kg"), HasSubstr("[0.001, 1] kg")));
}

TEST(CaterpillarParams, NonNumberIsRejected) {
  auto p = ParseCaterpillarParams(Edit("value: 8.8", "value: strong"), "copy.yaml");
  ASSERT_FALSE(p.ok());
  EXPECT_THAT(std::string(p.status().message()),
              AllOf(HasSubstr("actuators.force_n.value: must be a finite number"),
                    HasSubstr("'strong'")));
}

TEST(CaterpillarParams, MissingFieldIsNamedWithUnitAndRange) {
  auto p = ParseCaterpillarParams(Edit("    timestep_s:", "    # gone"), "copy.yaml");
  ASSERT_FALSE(p.ok());
  EXPECT_THAT(std::string(p.status().message()),
              AllOf(HasSubstr("copy.yaml"), HasSubstr("missing parameter simulation.timestep_s")));
}

TEST(CaterpillarParams, UnknownFieldIsAnError) {
  auto p = ParseCaterpillarParams(Edit("max_excursion_m:", "max_excursion_mm:"), "copy.yaml");
  ASSERT_FALSE(p.ok());
  EXPECT_THAT(std::string(p.status().message()),
              AllOf(HasSubstr("copy.yaml:" + std::to_string(LineOf("max_excursion_m:")) + ":"),
                    HasSubstr("simulation.max_excursion_mm: the caterpillar model has no such parameter")));
  // A parameter the structure uses, renamed: the structure's reference is named.
  auto q = ParseCaterpillarParams(Edit("size_y_m:", "size_yy_m:"), "copy.yaml");
  ASSERT_FALSE(q.ok());
  EXPECT_THAT(std::string(q.status().message()),
              HasSubstr("'lumps.size_y_m' is not a parameter of this robot; nearest: "));
}

TEST(CaterpillarParams, WholeNumberFieldsRejectFractions) {
  auto p = ParseCaterpillarParams(Edit("{value: 2, range: [0, 20]", "{value: 2.5, range: [0, 20]"),
                                  "copy.yaml");
  ASSERT_FALSE(p.ok());
  EXPECT_THAT(std::string(p.status().message()),
              AllOf(HasSubstr("simulation.settle_cycles = 2.5 cycles"), HasSubstr("whole number")));
}

TEST(CaterpillarParams, FrictionIsInfiniteOrACoefficient) {
  auto finite = ParseCaterpillarParams(Edit("value: infinite", "value: 0.8"), "copy.yaml");
  ASSERT_TRUE(finite.ok()) << finite.status();
  EXPECT_FALSE(finite->ground.infinite_friction);
  EXPECT_EQ(finite->ground.friction_coefficient, 0.8);
  auto bad = ParseCaterpillarParams(Edit("value: infinite", "value: sticky"), "copy.yaml");
  ASSERT_FALSE(bad.ok());
  EXPECT_THAT(std::string(bad.status().message()),
              AllOf(HasSubstr("ground.friction_coefficient.value"),
                    HasSubstr("a number or infinite"), HasSubstr("'sticky'")));
}

TEST(CaterpillarParams, InconsistentStrokeIsRejected) {
  auto p = ParseCaterpillarParams(Edit("value: 0.032", "value: 0.050"), "copy.yaml");
  ASSERT_FALSE(p.ok());
  EXPECT_THAT(std::string(p.status().message()), HasSubstr("rest actuator length"));
}

TEST(CaterpillarParams, EveryDescriptorNumberReachesTheModel) {
  // Each parameter of the built-in descriptor is a field of the model with its value.
  const CaterpillarParams& p = DefaultCaterpillarParams();
  for (const auto& param : CaterpillarDescriptor().parameters) {
    auto v = GetField(p, param.name);
    ASSERT_TRUE(v.ok()) << v.status();
    EXPECT_EQ(*v, param.value) << param.name;
  }
}

TEST(CaterpillarParams, ADescriptorOfAnotherRobotIsRefused) {
  std::string t = DefaultText();
  t.replace(t.find("name: caterpillar"), 17, "name: arm");
  auto p = ParseCaterpillarParams(t, "copy.yaml");
  ASSERT_FALSE(p.ok());
  EXPECT_THAT(std::string(p.status().message()), HasSubstr("robot 'arm' is not the caterpillar"));
}

TEST(CaterpillarParams, JsonTextIsAccepted) {
  // The built-in descriptor re-emitted as JSON (every scalar double-quoted, flow style).
  YAML::Emitter json;
  json.SetMapFormat(YAML::Flow);
  json.SetSeqFormat(YAML::Flow);
  json.SetStringFormat(YAML::DoubleQuoted);
  json << YAML::Load(DefaultText());
  ASSERT_EQ(json.c_str()[0], '{');
  auto p = ParseCaterpillarParams(json.c_str(), "inline.json");
  ASSERT_TRUE(p.ok()) << p.status();
  EXPECT_EQ(p->actuators.force_n, DefaultCaterpillarParams().actuators.force_n);
  EXPECT_EQ(p->simulation.timestep_s, DefaultCaterpillarParams().simulation.timestep_s);
}

TEST(CaterpillarParams, MissingFileIsNotFound) {
  auto p = LoadCaterpillarParams("/nonexistent/robot.yaml");
  ASSERT_FALSE(p.ok());
  EXPECT_THAT(std::string(p.status().message()), HasSubstr("/nonexistent/robot.yaml"));
}

}  // namespace
}  // namespace gaitforge::caterpillar
