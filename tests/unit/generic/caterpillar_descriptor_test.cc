// The caterpillar's descriptor (robots/caterpillar/robot.yaml): the built-in one holds the
// paper's robot, and each kind of mistake in a copy is reported with file, line, field,
// unit and allowed range. (The format's rules on a fixture robot: tests/unit/robots.)
#include <algorithm>
#include <cmath>
#include <string>

#include <yaml-cpp/yaml.h>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "robots/descriptor_parser.h"
#include "robots/registry.h"
#include "workers/models/generic/generic_world.h"

namespace gaitforge::generic {
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

// 1-based line of the first occurrence of `needle` in the built-in text.
int LineOf(const std::string& needle) {
  const std::string t = DefaultText();
  return 1 + static_cast<int>(std::count(t.begin(), t.begin() + t.find(needle), '\n'));
}

std::string ErrorOf(const std::string& text) {
  auto d = robots::ParseDescriptor(text, "copy.yaml");
  EXPECT_FALSE(d.ok());
  return d.ok() ? "" : std::string(d.status().message());
}

TEST(CaterpillarDescriptor, TheBuiltInFileHoldsThePapersRobot) {
  const ParamValues p(robots::Robot("caterpillar"));
  EXPECT_EQ(p("lumps.mass_kg"), 0.030);
  EXPECT_EQ(p("lumps.spacing_m"), 0.032);
  EXPECT_EQ(p("links.flexure.axial_stiffness_n_per_m"), 1040);
  EXPECT_EQ(p("links.segment.bending_stiffness_nm_per_rad"), 0.07);
  EXPECT_EQ(p("actuators.force_n"), 8.8);
  EXPECT_EQ(p("actuators.return_spring_n_per_m"), 63);
  EXPECT_NEAR(p("lumps.spacing_m") + p("actuators.front_attach_x_m") - p("actuators.rear_attach_x_m"),
              p("actuators.min_length_m"), 1e-12);  // the rest length is the stroke's start
  EXPECT_TRUE(std::isinf(p("ground.friction_coefficient")));
  EXPECT_EQ(p("simulation.settle_cycles"), 2);
  const auto& d = robots::Robot("caterpillar");
  EXPECT_EQ(d.bodies.size(), 6u);
  EXPECT_EQ(d.joints.size(), 5u);
  EXPECT_EQ(d.actuators.size(), 6u);
  EXPECT_EQ(d.controller.genes.size(), 13u);
}

TEST(CaterpillarDescriptor, OutOfRangeValueNamesFileLineFieldUnitAndRange) {
  EXPECT_THAT(ErrorOf(Edit("value: 0.030, range: [0.001, 1]", "value: -2, range: [0.001, 1]")),
              AllOf(HasSubstr("copy.yaml:" + std::to_string(LineOf("mass_kg:")) + ":"),
                    HasSubstr("lumps.mass_kg = -2 kg"), HasSubstr("[0.001, 1] kg")));
}

TEST(CaterpillarDescriptor, NonNumberIsRejected) {
  EXPECT_THAT(ErrorOf(Edit("value: 8.8", "value: strong")),
              AllOf(HasSubstr("actuators.force_n.value: must be a finite number"),
                    HasSubstr("'strong'")));
}

TEST(CaterpillarDescriptor, UnknownFieldIsAnErrorAndAMissingReferenceIsNamed) {
  EXPECT_THAT(ErrorOf(Edit("max_excursion_m:   {value: 5, range:", "max_excursion_m:   {value: 5, rang:")),
              AllOf(HasSubstr("copy.yaml:" + std::to_string(LineOf("max_excursion_m:")) + ":"),
                    HasSubstr("simulation.max_excursion_m.rang")));
  // A parameter the structure uses, renamed: the structure's reference is named.
  EXPECT_THAT(ErrorOf(Edit("size_y_m:", "size_yy_m:")),
              HasSubstr("'lumps.size_y_m' is not a parameter"));
}

TEST(CaterpillarDescriptor, WholeNumberFieldsRejectFractions) {
  EXPECT_THAT(ErrorOf(Edit("{value: 2, range: [0, 20]", "{value: 2.5, range: [0, 20]")),
              AllOf(HasSubstr("simulation.settle_cycles = 2.5 cycles"), HasSubstr("whole number")));
}

TEST(CaterpillarDescriptor, FrictionIsInfiniteOrACoefficient) {
  auto finite = robots::ParseDescriptor(Edit("value: infinite", "value: 0.8"), "copy.yaml");
  ASSERT_TRUE(finite.ok()) << finite.status();
  EXPECT_EQ(finite->Value("ground.friction_coefficient"), 0.8);
  EXPECT_THAT(ErrorOf(Edit("value: infinite", "value: sticky")),
              AllOf(HasSubstr("ground.friction_coefficient.value"), HasSubstr("'sticky'")));
}

TEST(CaterpillarDescriptor, InconsistentStrokeIsRejected) {
  EXPECT_THAT(ErrorOf(Edit("value: 0.032", "value: 0.050")), HasSubstr("rest actuator length"));
}

TEST(CaterpillarDescriptor, JsonTextIsAccepted) {
  // The built-in descriptor re-emitted as JSON (every scalar double-quoted, flow style).
  YAML::Emitter json;
  json.SetMapFormat(YAML::Flow);
  json.SetSeqFormat(YAML::Flow);
  json.SetStringFormat(YAML::DoubleQuoted);
  json << YAML::Load(DefaultText());
  ASSERT_EQ(json.c_str()[0], '{');
  auto d = robots::ParseDescriptor(json.c_str(), "inline.json");
  ASSERT_TRUE(d.ok()) << d.status();
  EXPECT_EQ(d->Value("actuators.force_n"), 8.8);
  EXPECT_EQ(d->Value("simulation.timestep_s"), 0.001);
  EXPECT_EQ(d->bodies.size(), 6u);
}

TEST(CaterpillarDescriptor, MissingFileIsNotFound) {
  auto d = robots::LoadDescriptor("/nonexistent/robot.yaml");
  ASSERT_FALSE(d.ok());
  EXPECT_THAT(std::string(d.status().message()), HasSubstr("/nonexistent/robot.yaml"));
}

}  // namespace
}  // namespace gaitforge::generic
