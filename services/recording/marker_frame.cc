// The frame check of marker positions (recording_internal.h, CheckMarkerFrame).
#include <algorithm>
#include <cmath>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "services/recording/recording_internal.h"

namespace gaitforge::recording::internal {
namespace {

double Median(std::vector<double> v) {
  const size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + mid, v.end());
  return v[mid];
}

std::string Metres(double v) { return absl::StrFormat("%.3g m", v); }

// How far the markers' line may turn from x in the x-y plane: the model is planar along x,
// and a lab frame turned by more (cos 10 degrees = 0.985) puts the travel into y.
constexpr double kMaxHeadingDeg = 10;

}  // namespace

absl::Status CheckMarkerFrame(const std::string& name, const RobotInfo& robot,
                              const Recording& rec) {
  if (robot.markers < 2 || robot.marker_pitch_m <= 0) return absl::OkStatus();
  struct Present {
    int marker;  // 1-based
    int column;  // index into rec.columns (x)
    int y;       // index of its y column, -1 without one
  };
  std::vector<Present> present;
  for (int i = 1; i <= robot.markers; ++i) {
    const int c = rec.ChannelIndex(absl::StrCat("m", i, ".x"));
    if (c >= 0) present.push_back({i, c, rec.ChannelIndex(absl::StrCat("m", i, ".y"))});
  }
  if (present.size() < 2) return absl::OkStatus();
  // Per pair of neighbouring present markers: the median over rows of their x (and y)
  // distance, per marker step; then the median over pairs. Robust to a marker swapped or
  // occluded for a while, and to the stretch of a stroke (at most a third of the pitch).
  auto spacing = [&](int a_col, int b_col, int steps) {
    const auto& a = rec.columns[a_col];
    const auto& b = rec.columns[b_col];
    std::vector<double> d(a.size());
    for (size_t r = 0; r < a.size(); ++r) d[r] = b[r] - a[r];
    return Median(std::move(d)) / steps;
  };
  std::vector<double> per_pair, per_pair_y;
  for (size_t k = 0; k + 1 < present.size(); ++k) {
    const int steps = present[k + 1].marker - present[k].marker;
    per_pair.push_back(spacing(present[k].column, present[k + 1].column, steps));
    if (present[k].y >= 0 && present[k + 1].y >= 0)
      per_pair_y.push_back(spacing(present[k].y, present[k + 1].y, steps));
  }
  const double pitch = Median(per_pair);
  const bool has_y = !per_pair_y.empty();
  const double pitch_y = has_y ? Median(per_pair_y) : 0.0;
  const double size = std::hypot(pitch, pitch_y);  // per marker step, in the x-y plane
  const Present& rear = present[0];
  const Present& next = present[1];
  const int column = next.column + 2;  // 1-based, after t
  const std::string pair = absl::StrCat("m", rear.marker, ".x and m", next.marker, ".x");
  const std::string expected =
      absl::StrCat("the ", robot.name, "'s neighbouring markers are about ",
                   Metres(robot.marker_pitch_m), " apart");
  // A robot scaled up tenfold still passes; centimetres (x31) and millimetres do not.
  if (size > 30 * robot.marker_pitch_m) {
    const double ratio = size / robot.marker_pitch_m;
    const char* unit = ratio > 300 ? "millimetres (divide every position by 1000)"
                                   : "centimetres (divide every position by 100)";
    return absl::InvalidArgumentError(absl::StrCat(
        name, ":1:", column, ": neighbouring markers are ", Metres(size), " apart along ",
        has_y ? "x and y" : "x", " (median over the recording, ", pair, "); ", expected,
        ": positions must be in metres, and these look like ", unit));
  }
  const double heading = std::atan2(pitch_y, pitch) * 180 / M_PI;
  if (pitch < -0.25 * robot.marker_pitch_m && std::abs(heading) > 180 - kMaxHeadingDeg)
    return absl::InvalidArgumentError(absl::StrCat(
        name, ":1:", column, ": m", next.marker, " is ", Metres(-pitch),
        " per marker behind m", rear.marker, " along x (median over the recording, ", pair,
        "); x must point forward and m1 be the rear marker: the x axis looks reversed, or the "
        "markers are numbered from the front"));
  if (size < 0.25 * robot.marker_pitch_m)
    return absl::InvalidArgumentError(absl::StrCat(
        name, ":1:", column, ": neighbouring markers are only ", Metres(size),
        " apart along ", has_y ? "x and y" : "x", " (median over the recording, ", pair,
        "); ", expected, ": x must point along the robot, from m1 (the rear) forward, and z "
        "up", has_y ? "" : "; if the lab's frame is turned about z, include the y columns "
        "and the message says by how much"));
  if (std::abs(heading) > kMaxHeadingDeg)
    return absl::InvalidArgumentError(absl::StrFormat(
        "%s:1:%d: the markers lie at %.0f degrees from x in the x-y plane (per marker "
        "step %s along x and %s along y, median over the recording, %s and their y); x must "
        "point along the robot, from m1 (the rear) forward: rotate the positions by %.0f "
        "degrees about z",
        name, column, heading, Metres(pitch), Metres(pitch_y), pair, -heading));
  return absl::OkStatus();
}

}  // namespace gaitforge::recording::internal
