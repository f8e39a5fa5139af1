#pragma once
// Recordings: a CSV of channels over time with a JSON sidecar (docs/recording-format.md).
// Parsed and validated here, with no gRPC, SQLite or ODE: the coordinator checks uploads
// with it and workers read what they fetched with it.
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/statusor.h"

namespace gaitforge::robots {
struct RobotDescriptor;
}

namespace gaitforge::recording {

// What the sidecar says.
struct RecordingMeta {
  std::string robot;                         // a robot name or descriptor (robots/)
  std::string parameters;                    // parameter file the robot was built with (path)
  std::map<std::string, double> overrides;   // parameter overrides (name -> value)
  std::string command_kind;                  // "gait"
  std::vector<double> genes;                 // the command: the gait genes of its robot
  std::string source;                        // "simulation" | "hardware" | free text
  std::string note;
  std::map<std::string, std::string> channel_units;  // optional channel metadata
};

struct Recording {
  std::vector<std::string> channels;            // column names after "t"
  std::vector<double> t;                        // seconds, strictly increasing
  std::vector<std::vector<double>> columns;     // columns[c][row], metres or radians
  RecordingMeta meta;
  double dt = 0;                                // nominal sampling interval (s)
  int dropped_rows = 0;                         // rows missing from the regular grid
  // Cells left empty or written NaN (an occluded marker): bridged in `columns` by linear
  // interpolation in time between the channel's neighbouring values (the first or last
  // value held at the ends). Per channel, and the positions for whoever wants to skip them.
  int64_t missing_cells = 0;
  std::vector<int64_t> missing_per_channel;        // one per channel; empty when none
  std::vector<std::vector<bool>> missing;          // missing[c][row]; empty when none
  int ChannelIndex(std::string_view name) const;  // -1 if absent
};

struct RecordingLimits {
  size_t max_bytes = 64u << 20;   // CSV plus sidecar
  size_t max_rows = 2000000;
  // Sampling may deviate from the nominal interval by this fraction of it; a gap of k
  // intervals (k >= 2, within the same tolerance) is k - 1 dropped rows.
  double irregular_tolerance = 0.05;
};

// Parses and validates. Errors name the file, line and column and what was expected:
// non-numeric cells, infinite values, an empty or NaN time, a channel with no value at all,
// missing or duplicate columns, time that does not increase, sampling irregular beyond the
// tolerance, an unknown robot or channel, a file over the size limit, a sidecar that is not
// JSON or lacks required keys, marker positions in mm or cm or with x reversed (from the
// markers' spacing). Empty or NaN channel cells are missing samples, bridged.
// `robot`, when given, is a robot of the caller's (a descriptor a study carries) that the
// sidecar may name besides the built-in ones; its sensors give the channels.
absl::StatusOr<Recording> ParseRecording(std::string_view csv, std::string_view sidecar,
                                         const std::string& csv_name,
                                         const std::string& sidecar_name,
                                         const RecordingLimits& limits = {},
                                         const robots::RobotDescriptor* robot = nullptr);

// The robot a sidecar names (its "robot"), checked as ParseRecording checks it: a built-in
// robot, or `robot` when given. Errors name the sidecar, line and column.
absl::StatusOr<std::string> SidecarRobot(std::string_view sidecar, const std::string& sidecar_name,
                                         const robots::RobotDescriptor* robot = nullptr);

// Whether two recordings' sampling intervals are one rate (within 1% of `first`): what one
// diagnosis or plan compares against one model must share it.
bool SameRate(double dt, double first);

// Content address: lowercase hex SHA-256 over the CSV bytes, a zero byte, the sidecar bytes.
std::string ContentHash(std::string_view csv, std::string_view sidecar);

// The sensor channels a robot's recordings may carry (its descriptor's sensors; besides
// them, its actuators' input channels, robots::Actuator::InputChannel); empty for an
// unknown robot.
std::vector<std::string> KnownChannels(const std::string& robot);

}  // namespace gaitforge::recording
