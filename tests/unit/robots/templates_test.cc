// Counts and repeats in descriptors (robots/templates.h, docs/robots.md "Counts and
// repeats"): the substitution, a repeated part read once per index with its errors pointing
// at the template's own line, and counts checked against their range.
#include "robots/templates.h"

#include <string>

#include "gtest/gtest.h"
#include "robots/descriptor_parser.h"
#include "robots/registry.h"

namespace gaitforge::robots {
namespace {

TEST(Substitute, NamesExpressionsAndPlainText) {
  const TemplateVariables vars = {{"k", 3}, {"lumps", 5}};
  EXPECT_EQ(*Substitute("disk$k", vars), "disk3");
  EXPECT_EQ(*Substitute("disk$(k-1)", vars), "disk2");
  EXPECT_EQ(*Substitute("-$(k/lumps)*arm.length_m", vars), "-0.59999999999999998*arm.length_m");
  EXPECT_EQ(*Substitute("$(lumps/5)*joint.k", vars), "1*joint.k");
  EXPECT_EQ(*Substitute("$(2*(k + 1) - -1)", vars), "9");
  EXPECT_EQ(*Substitute("no dollars here", vars), "no dollars here");
}

TEST(Substitute, SaysWhatIsWrong) {
  const TemplateVariables vars = {{"k", 3}};
  EXPECT_EQ(Substitute("disk$n", vars).status().message(),
            "unknown template variable $n (known here: k)");
  EXPECT_EQ(Substitute("$(k/0)", vars).status().message(), "division by zero at '' in $(k/0)");
  EXPECT_EQ(Substitute("$(k-", vars).status().message(), "'$(k-': missing ')'");
  EXPECT_EQ(Substitute("cost $5", vars).status().message(),
            "'$5': a '$' must start $name or $(expression)");
}

std::string ArmWithLumps(const std::string& lumps) {
  std::string text(BuiltinText("continuum_arm"));
  const std::string from = "lumps: {value: 5,";
  text.replace(text.find(from), from.size(), "lumps: {value: " + lumps + ",");
  return text;
}

TEST(Repeat, TheArmOfNLumpsIsBuiltFromOneTemplate) {
  auto d = ParseDescriptor(ArmWithLumps("12"), "arm12.yaml");
  ASSERT_TRUE(d.ok()) << d.status();
  ASSERT_EQ(d->bodies.size(), 12u);
  ASSERT_EQ(d->joints.size(), 12u);
  EXPECT_EQ(d->bodies[11].name, "disk12");
  EXPECT_EQ(d->joints[11].body1, "disk11");
  EXPECT_EQ(d->actuators[0].body2, "disk12");
  EXPECT_NEAR(d->bodies[11].position[2].Eval([&](const std::string& n) { return d->Value(n); }),
              -0.3, 1e-12);
  ASSERT_EQ(d->counts.size(), 1u);
  EXPECT_EQ(d->counts[0].value, 12);
  EXPECT_EQ(d->Channels().back(), "j12.angle2");
  // The built-in one: the paper's five.
  EXPECT_EQ(Robot("continuum_arm").bodies.size(), 5u);
}

TEST(Repeat, ACountOutsideItsRangeOrNotWholeIsRefused) {
  const auto one = ParseDescriptor(ArmWithLumps("1"), "arm.yaml");
  ASSERT_FALSE(one.ok());
  EXPECT_NE(one.status().message().find("arm.yaml:23:18: counts.lumps.value: 1 is outside its range [2, 40]"),
            std::string::npos) << one.status().message();
  const auto half = ParseDescriptor(ArmWithLumps("2.5"), "arm.yaml");
  ASSERT_FALSE(half.ok());
  EXPECT_NE(half.status().message().find("value and range must be whole numbers"), std::string::npos)
      << half.status().message();
}

TEST(Repeat, ErrorsPointAtTheTemplateAndSayWhichIndex) {
  std::string text(BuiltinText("continuum_arm"));
  const std::string from = "bodies: [disk$(k-1), disk$k]";
  const size_t at = text.find(from);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, from.size(), "bodies: [disk$(k-1), disk$(k+1)]");
  const auto d = ParseDescriptor(text, "arm.yaml");
  ASSERT_FALSE(d.ok());
  // The last joint names a disk past the end: joints[1] (k = 5), on the template's line.
  EXPECT_NE(d.status().message().find("joints[1] (k = 5).bodies"), std::string::npos)
      << d.status().message();
  EXPECT_NE(d.status().message().find("disk6"), std::string::npos) << d.status().message();
  EXPECT_EQ(d.status().message().rfind("arm.yaml:", 0), 0u);
  EXPECT_EQ(d.status().message().find("arm.yaml:0:"), std::string::npos);
}

}  // namespace
}  // namespace gaitforge::robots
