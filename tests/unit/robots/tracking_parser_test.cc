// A descriptor's tracking section (robots/tracking_parser.h): the arm's is read with its
// parameters, and a bad one is refused with the file, line, field and what is allowed.
#include <string>

#include "gtest/gtest.h"
#include "robots/descriptor_parser.h"
#include "robots/registry.h"

namespace gaitforge::robots {
namespace {

const std::string kLine =
    "tracking: {marker: tip, axes: [x, y], lever: 0.5*arm.length_m, kp: tracking.kp, ki: tracking.ki,\n"
    "           kd: tracking.kd, rate_hz: tracking.rate_hz, lead_s: tracking.lead_s}";

// The arm's descriptor with its tracking section replaced by `section`.
std::string ArmWith(const std::string& section) {
  std::string text(BuiltinText("continuum_arm"));
  const size_t at = text.find(kLine);
  EXPECT_NE(at, std::string::npos) << "the arm's tracking line moved; update this test";
  return text.replace(at, kLine.size(), section);
}

TEST(TrackingParserTest, TheArmTracksItsTipInXAndYWithThePapersGains) {
  const RobotDescriptor& arm = Robot("continuum_arm");
  ASSERT_TRUE(arm.tracking.has_value());
  EXPECT_EQ(arm.tracking->marker, "tip");
  EXPECT_EQ(arm.tracking->axes, (std::vector<int>{0, 1}));
  const auto value = [&arm](const std::string& n) { return arm.Value(n); };
  EXPECT_DOUBLE_EQ(arm.tracking->kp.Eval(value), 9.6);
  EXPECT_DOUBLE_EQ(arm.tracking->ki.Eval(value), 1.5);
  EXPECT_DOUBLE_EQ(arm.tracking->kd.Eval(value), 1.2);
  EXPECT_DOUBLE_EQ(arm.tracking->rate_hz.Eval(value), 50);
  EXPECT_DOUBLE_EQ(arm.tracking->lever.Eval(value), 0.15);
  EXPECT_FALSE(Robot("caterpillar").tracking.has_value());
}

struct BadCase {
  std::string name, section, message;
};

class TrackingParserErrorTest : public ::testing::TestWithParam<BadCase> {};

TEST_P(TrackingParserErrorTest, IsRefusedWithWhereAndWhy) {
  auto d = ParseDescriptor(ArmWith(GetParam().section), "arm.yaml");
  ASSERT_FALSE(d.ok());
  EXPECT_NE(std::string(d.status().message()).find(GetParam().message), std::string::npos)
      << d.status().message();
  EXPECT_NE(std::string(d.status().message()).find("arm.yaml:"), std::string::npos);
}

const std::string kRest =
    ", kp: tracking.kp, ki: tracking.ki, kd: tracking.kd, rate_hz: tracking.rate_hz, "
    "lead_s: tracking.lead_s}";

INSTANTIATE_TEST_SUITE_P(
    Cases, TrackingParserErrorTest,
    ::testing::Values(
        BadCase{"UnknownMarker", "tracking: {marker: base, axes: [x], lever: 0.1" + kRest,
                "no marker named 'base' (markers: tip)"},
        BadCase{"AxisNotRecorded", "tracking: {marker: tip, axes: [x, w], lever: 0.1" + kRest,
                "'w' is not an axis the marker records (x, y, z)"},
        BadCase{"AxisTwice", "tracking: {marker: tip, axes: [x, x], lever: 0.1" + kRest,
                "'x' is named twice"},
        BadCase{"LeverNotPositive", "tracking: {marker: tip, axes: [x], lever: 0" + kRest,
                "tracking.lever: must be > 0 (m)"},
        BadCase{"UnknownParameter", "tracking: {marker: tip, axes: [x], lever: arm.lenght_m" + kRest,
                "'arm.lenght_m' is not a parameter of this robot; nearest: arm.length_m"},
        BadCase{"UnknownKey", "tracking: {marker: tip, axes: [x], lever: 0.1, gain: 3" + kRest,
                "gain"},
        BadCase{"MissingGain", "tracking: {marker: tip, axes: [x], lever: 0.1, ki: 1, kd: 1, "
                               "rate_hz: 50, lead_s: 1}",
                "tracking.kp: missing"}),
    [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace gaitforge::robots
