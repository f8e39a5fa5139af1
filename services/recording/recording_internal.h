#pragma once
// Internals of the recording parser shared by recording.cc and sidecar.cc; not a public API.
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "robots/descriptor.h"
#include "services/recording/recording.h"

namespace gaitforge::recording::internal {

// A robot that recordings may describe.
struct RobotInfo {
  std::string name;                   // the robot's name in robots/
  std::vector<std::string> channels;  // the CSV columns it may carry, besides "t"
  // Its actuators' input channels (part of `channels`): a "playback" command needs every one.
  std::vector<std::string> inputs;
  std::map<std::string, std::string> units;  // channel -> unit, for every channel
  int gene_count = 0;                 // length of command.genes for kind "gait"
  std::string gene_names;             // for messages: "a_T1 a_T2 ... T"
  // Markers m1..m<markers> from the rear to the front, `marker_pitch_m` apart along x at
  // rest (the canonical geometry); 0 markers: no frame check.
  int markers = 0;
  double marker_pitch_m = 0;
};

// What a recording of robot d may hold: its sensors' channels, its controller's genes.
RobotInfo InfoOf(const robots::RobotDescriptor& d);
const RobotInfo* FindRobot(std::string_view name);  // a built-in robot; nullptr when unknown
std::string KnownRobots();                          // the names, comma-separated

// The unit a sensor channel's values are in: "rad" for "<joint>.angle" (and a universal
// joint's ".angle1", ".angle2"), "m" otherwise (markers).
std::string UnitOf(std::string_view channel);

// `s` for a message: C-escaped, cut to 40 bytes with "..." after.
std::string Quote(std::string_view s);

// A UTF-8 byte order mark at the start, if any, removed.
std::string_view StripBom(std::string_view s);

// Parses a decimal or exponent number (optional sign, no hex, no inf/nan) that must span
// all of `s`. Values too small for a double become 0 or subnormal; false for anything else
// that is not a finite number.
bool ParseFiniteDouble(std::string_view s, double* out);

struct Sidecar {
  RecordingMeta meta;
  const RobotInfo* robot = nullptr;
  // Where each entry of "channels" is (1-based line, column), to report one that the CSV
  // lacks.
  std::map<std::string, std::pair<int, int>> channel_marks;
  std::pair<int, int> command_mark;  // where command.kind is
};

// Strict JSON (RFC 8259) syntax check; errors as NAME:LINE:COLUMN: not valid JSON: ...
absl::Status CheckJsonSyntax(std::string_view text, const std::string& name);

// Parses and validates the sidecar (docs/recording-format.md, "Sidecar"); `robot`, when
// given, is the robot a sidecar of that name describes (before the built-in ones).
absl::StatusOr<Sidecar> ParseSidecar(std::string_view text, const std::string& name,
                                     const RobotInfo* robot = nullptr);

// Catches the two usual export mistakes in marker positions, from the spacing of adjacent
// markers along x (median over the recording): a file in millimetres or centimetres, and an
// x axis that points backwards (or markers numbered from the front). Errors point at the
// header column (docs/recording-format.md, "Frame and units").
absl::Status CheckMarkerFrame(const std::string& name, const RobotInfo& robot,
                              const Recording& rec);

}  // namespace gaitforge::recording::internal
