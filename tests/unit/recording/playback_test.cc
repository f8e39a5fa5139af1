// Playback recordings (docs/recording-format.md, "command"): the actuators' input columns
// (robots::Actuator::InputChannel) drive the robot, so a playback needs every one of them,
// has no genes, and the columns' units are the actuators' (N for a tendon's force).
#include <algorithm>
#include <string>

#include "gtest/gtest.h"
#include "services/recording/recording.h"

namespace gaitforge::recording {
namespace {

const std::string kCsv =
    "t,tip.x,tip.y,tip.z,rod1.force,rod2.force,rod3.force\n"
    "0,0,0,-0.3,0.3,0.3,-0.1\n"
    "0.01,0.0001,0.0001,-0.3,0.3,0.3,-0.1\n"
    "0.02,0.0003,0.0004,-0.3,0.3,0.3,-0.1\n";

std::string Sidecar(const std::string& command, const std::string& extra = "") {
  return "{\"robot\": \"continuum_arm\",\n \"command\": " + command + extra + "}";
}

TEST(PlaybackTest, ParsesInputColumnsBesideTheSensors) {
  auto r = ParseRecording(kCsv, Sidecar("{\"kind\": \"playback\"}",
                                        ",\n \"channels\": {\"rod2.force\": {\"unit\": \"N\"}}"),
                          "arm.csv", "arm.csv.json");
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->meta.command_kind, "playback");
  EXPECT_TRUE(r->meta.genes.empty());
  ASSERT_GE(r->ChannelIndex("rod3.force"), 0);
  EXPECT_DOUBLE_EQ(r->columns[r->ChannelIndex("rod3.force")][1], -0.1);
  EXPECT_EQ(r->meta.channel_units.at("rod2.force"), "N");
}

TEST(PlaybackTest, KnownChannelsAreTheSensorsOnly) {
  const auto known = KnownChannels("continuum_arm");
  EXPECT_NE(std::find(known.begin(), known.end(), "tip.x"), known.end());
  EXPECT_EQ(std::find(known.begin(), known.end(), "rod1.force"), known.end());
}

TEST(PlaybackTest, NeedsEveryActuatorsColumn) {
  const std::string csv =
      "t,tip.x,rod1.force,rod2.force\n0,0,0.3,0.3\n0.01,0.0001,0.3,0.3\n";
  auto r = ParseRecording(csv, Sidecar("{\"kind\": \"playback\"}"), "arm.csv", "arm.csv.json");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().message(),
            "arm.csv.json:2:22: key 'command.kind': a playback drives every actuator from its "
            "column, and arm.csv has no column 'rod3.force' (needed: rod1.force, rod2.force, "
            "rod3.force)");
}

TEST(PlaybackTest, HasNoGenes) {
  auto r = ParseRecording(kCsv, Sidecar("{\"kind\": \"playback\", \"genes\": []}"), "arm.csv",
                          "arm.csv.json");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("arm.csv.json:2:43: key 'command.genes': a playback has no genes"),
            std::string::npos)
      << r.status().message();
}

TEST(PlaybackTest, InputUnitIsTheActuators) {
  auto r = ParseRecording(kCsv, Sidecar("{\"kind\": \"playback\"}",
                                        ",\n \"channels\": {\"rod1.force\": {\"unit\": \"m\"}}"),
                          "arm.csv", "arm.csv.json");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("channel 'rod1.force' is in N, not 'm'"), std::string::npos)
      << r.status().message();
}

TEST(PlaybackTest, AGaitRecordingMayCarryInputsToo) {
  // The arm's hold controller has no genes; its recordings may still log the rod forces.
  auto r = ParseRecording(kCsv, Sidecar("{\"kind\": \"gait\", \"genes\": []}"), "arm.csv",
                          "arm.csv.json");
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->meta.command_kind, "gait");
}

}  // namespace
}  // namespace gaitforge::recording
