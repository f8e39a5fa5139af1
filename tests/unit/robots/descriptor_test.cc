// Robot descriptors (robots/): the built-in robots parse and say what they offer, and each
// kind of mistake in a descriptor is reported with file:line:column, field and allowed range.
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "robots/descriptor_parser.h"
#include "robots/registry.h"

namespace gaitforge::robots {
namespace {

using ::testing::AllOf;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

// A small robot that exists only as this text.
constexpr char kTwoBox[] = R"(format: gaitforge.robot.v1
name: twobox
model: generic
parameters:
  body:
    mass_kg: {value: 0.1, range: [0.001, 1], unit: kg, calibrate: true}
    length_m: {value: 0.05, range: [0.01, 1], unit: m}
  hinge:
    stiffness_nm_per_rad: {value: 0.5, range: [0, 10], unit: N m/rad, calibrate: true}
scales:
  stiffness: {doc: the hinge, multiplies: [hinge.stiffness_nm_per_rad]}
relations:
  - {check: "body.length_m >= body.mass_kg - body.length_m", why: "a test relation"}
controller:
  kind: phase_onoff
  actuators: [servo]
  period_s: [0.5, 2]
sensors:
  - {kind: joint_angle, names: [hinge]}
  - {kind: marker, names: [tip], axes: [x, z]}
)";

std::string Edit(const std::string& from, const std::string& to) {
  std::string t = kTwoBox;
  const size_t at = t.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return t.replace(at, from.size(), to);
}

std::string ErrorOf(const std::string& text) {
  auto d = ParseDescriptor(text, "twobox.yaml");
  EXPECT_FALSE(d.ok());
  return d.ok() ? "" : std::string(d.status().message());
}

TEST(Descriptor, EveryBuiltInRobotParses) {
  ASSERT_FALSE(RobotNames().empty());
  for (const std::string& name : RobotNames()) {
    const RobotDescriptor* d = FindRobot(name);
    ASSERT_NE(d, nullptr) << name;
    EXPECT_EQ(d->name, name);
    // A gait robot has genes; a robot whose controller holds (the arm) has none.
    EXPECT_EQ(d->controller.genes.empty(), d->controller.kind == "hold") << name;
  }
  EXPECT_EQ(FindRobot("no-such-robot"), nullptr);
  EXPECT_THROW(Robot("no-such-robot"), std::out_of_range);
}

TEST(Descriptor, TheCaterpillarOffersItsGenesChannelsAndParameters) {
  const RobotDescriptor& d = Robot("caterpillar");
  ASSERT_EQ(d.controller.genes.size(), 13u);
  EXPECT_EQ(d.controller.genes[0].name, "a_T1");
  EXPECT_EQ(d.controller.genes[6].name, "d_T1");
  EXPECT_EQ(d.controller.genes[12].name, "T");
  EXPECT_EQ(d.controller.genes[12].lo, 0.2);
  EXPECT_EQ(d.controller.genes[12].hi, 2.0);
  const auto channels = d.Channels();
  ASSERT_EQ(channels.size(), 18u);
  EXPECT_EQ(channels[0], "m1.x");
  EXPECT_EQ(channels[17], "m6.z");
  EXPECT_EQ(d.MarkerCount(), 6);
  EXPECT_EQ(d.MarkerSpacing(), 0.032);
  EXPECT_EQ(d.Value("actuators.force_n"), 8.8);
  EXPECT_TRUE(std::isinf(d.Value("ground.friction_coefficient")));
  const auto names = d.CalibratableNames();
  EXPECT_NE(std::find(names.begin(), names.end(), "scale.link_stiffness"), names.end());
  EXPECT_EQ(std::find(names.begin(), names.end(), "lumps.size_x_m"), names.end());
}

TEST(Descriptor, ASmallRobotExistsAsText) {
  auto d = ParseDescriptor(kTwoBox, "twobox.yaml");
  ASSERT_TRUE(d.ok()) << d.status();
  EXPECT_EQ(d->name, "twobox");
  EXPECT_THAT(d->Channels(), ElementsAre("hinge.angle", "tip.x", "tip.z"));
  ASSERT_EQ(d->controller.genes.size(), 3u);
  EXPECT_EQ(d->controller.genes[2].lo, 0.5);
  EXPECT_THAT(d->CalibratableNames(),
              ElementsAre("body.mass_kg", "hinge.stiffness_nm_per_rad", "scale.stiffness"));
  EXPECT_EQ(d->FindParameter("body.mass_kg")->mark.line, 6);
}

TEST(Descriptor, UnknownFieldNamesTheNearest) {
  EXPECT_THAT(ErrorOf(Edit("calibrate: true}", "calibrat: true}")),
              AllOf(HasSubstr("twobox.yaml:6:"), HasSubstr("body.mass_kg.calibrat: unknown field"),
                    HasSubstr("did you mean calibrate")));
}

TEST(Descriptor, FiguresMustBeKnownKinds) {
  EXPECT_THAT(ErrorOf(Edit("model: generic\n", "model: generic\nfigures: [paper_gait, waves]\n")),
              AllOf(HasSubstr("figures[1]"), HasSubstr("'waves' is not a figure kind"),
                    HasSubstr("known: paper_gait")));
  EXPECT_EQ(Robot("caterpillar").figures, std::vector<std::string>{"paper_gait"});
}

TEST(Descriptor, AKeyWrittenTwiceNamesBothLines) {
  EXPECT_THAT(ErrorOf(Edit("  hinge:\n", "  body:\n")),
              AllOf(HasSubstr("twobox.yaml:8:3: body: written twice"), HasSubstr("line 5")));
}

TEST(Descriptor, NegativeOrZeroMassGivesTheRange) {
  EXPECT_THAT(ErrorOf(Edit("{value: 0.1,", "{value: -0.1,")),
              AllOf(HasSubstr("twobox.yaml:6:22: body.mass_kg = -0.1 kg is outside [0.001, 1] kg")));
  EXPECT_THAT(ErrorOf(Edit("{value: 0.1,", "{value: 0,")), HasSubstr("is outside [0.001, 1] kg"));
}

TEST(Descriptor, NanOrInfiniteSpringConstantIsRefused) {
  EXPECT_THAT(ErrorOf(Edit("{value: 0.5,", "{value: .nan,")),
              AllOf(HasSubstr("twobox.yaml:9:"),
                    HasSubstr("hinge.stiffness_nm_per_rad.value: must be a finite number, got '.nan'")));
  EXPECT_THAT(ErrorOf(Edit("{value: 0.5,", "{value: .inf,")), HasSubstr("must be a finite number"));
}

TEST(Descriptor, NamesOfMissingParametersAreRefused) {
  EXPECT_THAT(ErrorOf(Edit("multiplies: [hinge.stiffness_nm_per_rad]", "multiplies: [hinge.stifness]")),
              AllOf(HasSubstr("scales.stiffness.multiplies: 'hinge.stifness' is not a parameter"),
                    HasSubstr("nearest: hinge.stiffness_nm_per_rad")));
  EXPECT_THAT(ErrorOf(Edit("body.length_m >= body.mass_kg", "body.length_m >= body.masss")),
              HasSubstr("relations[0]: 'body.masss' is not a parameter"));
}

// A robot's own suspects: calibratable parameters or scales with a range that holds the
// model's value; every mistake names its line and field.
TEST(Descriptor, SuspectsFitCalibratableNamesInRangesHoldingTheModel) {
  const std::string suspects = R"(suspects:
  hinge.too_stiff:
    name: Hinge stiffness
    meaning: the hinge was measured on another part
    where: every swing off in amplitude
    experiment: a static deflection test
    fit: {hinge.stiffness_nm_per_rad: [0.1, 2], scale.stiffness: [0.5, 2]}
relations:)";
  auto d = ParseDescriptor(Edit("relations:", suspects), "twobox.yaml");
  ASSERT_TRUE(d.ok()) << d.status();
  ASSERT_EQ(d->suspects.size(), 1u);
  const Suspect& s = d->suspects[0];
  EXPECT_EQ(s.id, "hinge.too_stiff");
  ASSERT_EQ(s.fit.size(), 2u);
  EXPECT_EQ(s.fit[0].nominal, 0.5);
  EXPECT_EQ(s.fit[0].unit, "N m/rad");
  EXPECT_EQ(s.fit[1].nominal, 1);
  auto error = [&](const std::string& from, const std::string& to) {
    std::string t = Edit("relations:", suspects);
    t.replace(t.find(from), from.size(), to);
    return ErrorOf(t);
  };
  EXPECT_THAT(error("hinge.stiffness_nm_per_rad: [0.1, 2]", "body.length_m: [0.02, 0.1]"),
              AllOf(HasSubstr("twobox.yaml:18:11:"), HasSubstr("suspects.hinge.too_stiff.fit.body.length_m"),
                    HasSubstr("not a calibratable parameter")));
  EXPECT_THAT(error("[0.1, 2]", "[0.1, 20]"), HasSubstr("must lie inside hinge.stiffness_nm_per_rad's range [0, 10]"));
  EXPECT_THAT(error("[0.1, 2]", "[0.6, 2]"), HasSubstr("must hold the model's own value 0.5"));
  EXPECT_THAT(error("[0.5, 2]}", "[0, 2]}"), HasSubstr("a scale's range must be positive"));
  EXPECT_THAT(error("    where: every swing off in amplitude\n", ""),
              HasSubstr("suspects.hinge.too_stiff.where"));
  EXPECT_THAT(error("    fit: {hinge.stiffness_nm_per_rad: [0.1, 2], scale.stiffness: [0.5, 2]}\n", ""),
              HasSubstr("NAME: [lo, hi]"));
}

// Physics the build rules out: each id with a non-empty reason and where it was written.
TEST(Descriptor, RuledOutEffectsKeepTheirReasonAndLine) {
  const std::string ruled = "ruled_out:\n  tether.constant: battery on board\nrelations:";
  auto d = ParseDescriptor(Edit("relations:", ruled), "twobox.yaml");
  ASSERT_TRUE(d.ok()) << d.status();
  ASSERT_EQ(d->ruled_out.size(), 1u);
  EXPECT_EQ(d->ruled_out[0].id, "tether.constant");
  EXPECT_EQ(d->ruled_out[0].why, "battery on board");
  EXPECT_EQ(d->ruled_out[0].mark.ToString(), "twobox.yaml:13:3");
  EXPECT_THAT(ErrorOf(Edit("relations:", "ruled_out:\n  tether.constant: ''\nrelations:")),
              AllOf(HasSubstr("twobox.yaml:13:"), HasSubstr("ruled_out.tether.constant: needs the reason")));
  EXPECT_THAT(ErrorOf(Edit("relations:", "ruled_out: [tether.constant]\nrelations:")),
              HasSubstr("ruled_out: expected a mapping EFFECT_ID: WHY"));
  EXPECT_THAT(ErrorOf(Edit("relations:", "ruled_out:\n  a: x\n  a: y\nrelations:")),
              HasSubstr("ruled_out"));
}

TEST(Descriptor, ARelationThatFailsSaysWhy) {
  EXPECT_THAT(ErrorOf(Edit("{value: 0.05, range: [0.01, 1]", "{value: 0.02, range: [0.01, 1]")),
              AllOf(HasSubstr("twobox.yaml:13:"), HasSubstr("fails"), HasSubstr("a test relation")));
  EXPECT_THAT(ErrorOf(Edit("body.length_m >= body.mass_kg", "body.length_m body.mass_kg")),
              HasSubstr("must read 'A + B - C <= D'"));
}

TEST(Descriptor, ControllerAndSensorMistakes) {
  EXPECT_THAT(ErrorOf(Edit("kind: phase_onoff", "kind: cpg9")),
              AllOf(HasSubstr("controller.kind: unknown kind 'cpg9'"), HasSubstr("phase_onoff")));
  EXPECT_THAT(ErrorOf(Edit("period_s: [0.5, 2]", "period_s: [2, 0.5]")),
              HasSubstr("controller.period_s: lo must not exceed hi"));
  EXPECT_THAT(ErrorOf(Edit("axes: [x, z]", "axes: [x, w]")), HasSubstr("each axis must be x, y or z"));
  EXPECT_THAT(ErrorOf(Edit("{kind: marker, names: [tip], axes: [x, z]}", "{kind: joint_angle, names: [hinge]}")),
              HasSubstr("channel hinge.angle is declared twice"));
  EXPECT_THAT(ErrorOf(Edit("controller:\n  kind: phase_onoff\n  actuators: [servo]\n  period_s: [0.5, 2]\n", "")),
              HasSubstr("controller: missing"));
}

TEST(Descriptor, WrongFormatSyntaxAndFilesAreNamed) {
  EXPECT_THAT(ErrorOf(Edit("gaitforge.robot.v1", "gaitforge.robot.v9")),
              HasSubstr("twobox.yaml:1:9: format: must be \"gaitforge.robot.v1\""));
  EXPECT_THAT(ErrorOf(Edit("period_s: [0.5, 2]", "period_s: [0.5, 2")), HasSubstr("twobox.yaml:"));
  const std::string dir = std::filesystem::temp_directory_path().string();
  auto d = LoadDescriptor(dir);
  ASSERT_FALSE(d.ok());
  EXPECT_THAT(std::string(d.status().message()), HasSubstr("is a directory"));
  d = LoadDescriptor("/nonexistent/robot.yaml");
  EXPECT_EQ(d.status().code(), absl::StatusCode::kNotFound);
}

TEST(Descriptor, NearestRanksByEditDistance) {
  EXPECT_THAT(Nearest("scale.link_stifness", {"scale.mass", "scale.link_stiffness", "lumps.mass_kg"}, 1),
              ElementsAre("scale.link_stiffness"));
}

}  // namespace
}  // namespace gaitforge::robots

namespace gaitforge::robots {
namespace {

// The structure sections, on the fixture robots (tests/fixtures/robots/NAME/robot.yaml).
std::string Fixture(const std::string& name = "twobox") {
  std::ifstream in(std::string(GAITFORGE_SOURCE_DIR) + "/tests/fixtures/robots/" + name + "/robot.yaml");
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The parse error of descriptor text `t` (read as `source`) with its first `from` replaced
// by `to`.
std::string EditedError(std::string t, const std::string& source, const std::string& from,
                        const std::string& to) {
  const size_t at = t.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  t.replace(at, from.size(), to);
  auto d = ParseDescriptor(t, source);
  EXPECT_FALSE(d.ok()) << from;
  return d.ok() ? "" : std::string(d.status().message());
}

// The same for fixture `name`.
std::string FixtureError(const std::string& from, const std::string& to,
                         const std::string& name = "twobox") {
  return EditedError(Fixture(name), name + ".yaml", from, to);
}

TEST(Structure, TheFixtureRobotParses) {
  auto d = ParseDescriptor(Fixture(), "twobox.yaml");
  ASSERT_TRUE(d.ok()) << d.status();
  ASSERT_EQ(d->bodies.size(), 2u);
  ASSERT_EQ(d->joints.size(), 1u);
  ASSERT_EQ(d->actuators.size(), 1u);
  const auto value = [&](const std::string& n) { return d->Value(n); };
  EXPECT_DOUBLE_EQ(d->bodies[1].position[0].Eval(value), 0.03 + 0.006 + 0.02);
  EXPECT_THAT(d->Channels(), ElementsAre("hinge.angle", "tail.x", "tail.z", "nose.x", "nose.z"));
  ASSERT_EQ(d->controller.genes.size(), 4u);
  EXPECT_EQ(d->controller.genes[1].name, "amp_servo");
}

TEST(Structure, NamesOfMissingPartsAreRefused) {
  EXPECT_THAT(FixtureError("bodies: [rear, front]", "bodies: [rear, frnt]"),
              AllOf(HasSubstr("joints[0].bodies[1]: no body named 'frnt'"),
                    HasSubstr("bodies: rear, front")));
  EXPECT_THAT(FixtureError("joint: hinge,", "joint: knee,"),
              HasSubstr("actuators[0].joint: no joint named 'knee'"));
  EXPECT_THAT(FixtureError("mass: rear.mass_kg", "mass: rear.mass_g"),
              AllOf(HasSubstr("bodies[0].mass: 'rear.mass_g' is not a parameter"),
                    HasSubstr("nearest: rear.mass_kg")));
  EXPECT_THAT(FixtureError("names: [hinge]", "names: [knee]"), HasSubstr("no joint named 'knee'"));
}

TEST(Structure, GenesMustMatchTheActuators) {
  EXPECT_THAT(FixtureError("actuators: [servo]", "actuators: [servo, wheel]"),
              HasSubstr("controller.actuators: must name each declared actuator once (servo)"));
}

TEST(Structure, ExpressionsAndAxesAreChecked) {
  EXPECT_THAT(FixtureError("position: [0, 0, 0.5*height_m]", "position: [0, 0, 0.5**height_m]"),
              HasSubstr("is not a number, a parameter name or a sum of terms"));
  EXPECT_THAT(FixtureError("axis: [0, 1, 0]", "axis: [0, 2, 0]"), HasSubstr("must be a unit vector"));
  EXPECT_THAT(FixtureError("type: servo", "type: motor"), HasSubstr("must be servo, piston or tendon"));
  EXPECT_THAT(FixtureError("type: servo", "type: piston"),
              HasSubstr("actuators[0].joint: unknown field"));
}

// Spheres (tests/fixtures/robots/balls/robot.yaml): a radius, its size 2r on each axis.
TEST(Structure, SpheresTakeARadius) {
  auto d = ParseDescriptor(Fixture("balls"), "balls.yaml");
  ASSERT_TRUE(d.ok()) << d.status();
  EXPECT_EQ(d->bodies[0].shape, "sphere");
  const auto value = [&](const std::string& n) { return d->Value(n); };
  for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(d->bodies[0].size[k].Eval(value), 0.05);
  EXPECT_THAT(FixtureError("radius: ball.radius_m,", "size: [0.1, 0.1, 0.1],", "balls"),
              HasSubstr("bodies[0].size: a sphere takes radius, not size"));
  EXPECT_THAT(FixtureError("shape: sphere,", "shape: cylinder,", "balls"),
              HasSubstr("bodies[0].shape: must be box or sphere"));
  EXPECT_THAT(FixtureError("radius: ball.radius_m,", "radius: ball.radius,", "balls"),
              HasSubstr("'ball.radius' is not a parameter"));
  EXPECT_THAT(FixtureError("shape: box,", "shape: box, radius: 0.1,"),
              HasSubstr("a box takes size, not radius"));
}

// Universal joints and the world frame (tests/fixtures/robots/cantilever/robot.yaml).
std::string CantileverError(const std::string& from, const std::string& to) {
  return FixtureError(from, to, "cantilever");
}

TEST(Structure, UniversalJointsHoldTwoAxesAndSpringsPerAxis) {
  auto d = ParseDescriptor(Fixture("cantilever"), "cantilever.yaml");
  ASSERT_TRUE(d.ok()) << d.status();
  const Joint& j1 = d->joints[0];
  EXPECT_EQ(j1.type, "universal");
  EXPECT_EQ(j1.body1, kWorldBody);
  EXPECT_EQ(j1.axis2[2], 1.0);
  const auto value = [&](const std::string& n) { return d->Value(n); };
  EXPECT_DOUBLE_EQ(j1.stiffness->Eval(value), 2.0);
  EXPECT_DOUBLE_EQ(j1.stiffness2->Eval(value), 1.0);
  EXPECT_DOUBLE_EQ(j1.damping2->Eval(value), 0.001);
  EXPECT_FALSE(j1.rest.has_value());
  EXPECT_THAT(d->Channels(), ElementsAre("j1.angle1", "j1.angle2", "j2.angle1", "j2.angle2",
                                         "j3.angle1", "j3.angle2", "tip.x", "tip.y", "tip.z"));
  EXPECT_EQ(d->controller.kind, "hold");
  EXPECT_TRUE(d->controller.genes.empty());
}

TEST(Structure, UniversalJointAndWorldMistakesAreNamed) {
  EXPECT_THAT(CantileverError("axis2: [0, 0, 1],", "axis2: [1, 0, 0], lo: -1, hi: 1,"),
              HasSubstr("a universal joint takes no stops"));
  EXPECT_THAT(CantileverError("axis2: [0, 0, 1],", "axis2: [0.6, 0.8, 0],"),
              HasSubstr("joints[0].axis2: must be perpendicular to axis"));
  EXPECT_THAT(CantileverError("axis2: [0, 0, 1],", ""), HasSubstr("joints[0].axis2: must be [x, y, z]"));
  EXPECT_THAT(CantileverError("bodies: [world, l1]", "bodies: [l1, world]"),
              HasSubstr("the world frame may only be a joint's first body"));
  EXPECT_THAT(CantileverError("{name: l1,", "{name: world,"),
              HasSubstr("'world' names the fixed world frame in joints, not a body"));
  EXPECT_THAT(CantileverError("damping: [joint.bend_damping_nms_per_rad, joint.side_damping_nms_per_rad]}",
                              "damping: [joint.bend_damping_nms_per_rad]}"),
              HasSubstr("joints[0].damping: must be one value for both axes or [AXIS1, AXIS2]"));
  EXPECT_THAT(CantileverError("type: universal", "type: ball"), HasSubstr("must be hinge, universal, fixed or spring_link"));
  EXPECT_THAT(FixtureError("axis: [0, 1, 0],", "axis: [0, 1, 0], axis2: [0, 0, 1],"),
              HasSubstr("only a universal joint has axis2"));
}

TEST(Expr, ParsesLinearSums) {
  auto e = ParseExpr("0.5*a.b + c - 2 + d*3 - 1e-3");
  ASSERT_TRUE(e.ok()) << e.status();
  const double v = e->Eval([](const std::string& n) { return n == "a.b" ? 4.0 : n == "c" ? 1.0 : 2.0; });
  EXPECT_DOUBLE_EQ(v, 0.5 * 4 + 1 - 2 + 2 * 3 - 1e-3);
  EXPECT_FALSE(ParseExpr("").ok());
  EXPECT_FALSE(ParseExpr("a b").ok());
  EXPECT_FALSE(ParseExpr("3*").ok());
}

// Spring links, pistons and the plane (the caterpillar's structure, robots/caterpillar).
std::string CaterpillarError(const std::string& from, const std::string& to) {
  return EditedError(std::string(BuiltinText("caterpillar")), "caterpillar.yaml", from, to);
}

TEST(Structure, SpringLinkAndPistonMistakesAreNamed) {
  struct Case {
    std::string from, to, says;
  };
  const std::vector<Case> cases = {
      {"plane: xz", "plane: xy", "plane: must be xz"},
      {"plane: xz", "", "joints[0].type: a spring_link needs a planar robot"},
      {"axis: [1, 0, 0], length", "axis: [0, 1, 0], length", "joints[0].axis: must lie in the robot's plane"},
      {"length: 0.5*lumps.spacing_m, ", "", "joints[0].length: missing"},
      {"damping_ratio: links.bending_damping_ratio}", "damping_ratio: links.bending_damping_ratio, lo: -1}",
       "joints[0].lo: unknown field"},
      {"bodies: [lump1, lump2],\n     attach1", "bodies: [lump1, lump9],\n     attach1",
       "actuators[0].bodies[1]: no body named 'lump9'"},
      {"stop_erp: actuators.stop_erp,", "stop_erp: stop.erp,", "actuators[0].stop_erp: 'stop.erp' is not a parameter"},
      {"self_contact: true", "self_contact: maybe", "self_contact"},
      {"distance: caterpillar.distance", "distance: robot.distance",
       "objectives.distance: must be a dotted name such as caterpillar.distance, outside robot.*"},
      {"distance: caterpillar.distance", "walk: caterpillar.walk", "objectives.walk: unknown field"},
  };
  for (const Case& c : cases) EXPECT_THAT(CaterpillarError(c.from, c.to), HasSubstr(c.says)) << c.from;
}

}  // namespace
}  // namespace gaitforge::robots
