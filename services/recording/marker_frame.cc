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

}  // namespace

absl::Status CheckMarkerFrame(const std::string& name, const RobotInfo& robot,
                              const Recording& rec) {
  if (robot.markers < 2 || robot.marker_pitch_m <= 0) return absl::OkStatus();
  struct Present {
    int marker;  // 1-based
    int column;  // index into rec.columns
  };
  std::vector<Present> present;
  for (int i = 1; i <= robot.markers; ++i) {
    const int c = rec.ChannelIndex(absl::StrCat("m", i, ".x"));
    if (c >= 0) present.push_back({i, c});
  }
  if (present.size() < 2) return absl::OkStatus();
  // Per pair of neighbouring present markers: the median over rows of their x distance, per
  // marker step; then the median over pairs. Robust to a marker swapped or occluded for a
  // while, and to the stretch of a stroke (at most a third of the pitch).
  std::vector<double> per_pair;
  for (size_t k = 0; k + 1 < present.size(); ++k) {
    const auto& a = rec.columns[present[k].column];
    const auto& b = rec.columns[present[k + 1].column];
    std::vector<double> d(a.size());
    for (size_t r = 0; r < a.size(); ++r) d[r] = b[r] - a[r];
    per_pair.push_back(Median(std::move(d)) / (present[k + 1].marker - present[k].marker));
  }
  const double pitch = Median(per_pair);
  const Present& rear = present[0];
  const Present& next = present[1];
  const int column = next.column + 2;  // 1-based, after t
  const std::string pair = absl::StrCat("m", rear.marker, ".x and m", next.marker, ".x");
  const std::string expected =
      absl::StrCat("the ", robot.name, "'s neighbouring markers are about ",
                   Metres(robot.marker_pitch_m), " apart");
  // A robot scaled up tenfold still passes; centimetres (x31) and millimetres do not.
  if (pitch > 30 * robot.marker_pitch_m) {
    const double ratio = pitch / robot.marker_pitch_m;
    const char* unit = ratio > 300 ? "millimetres (divide every position by 1000)"
                                   : "centimetres (divide every position by 100)";
    return absl::InvalidArgumentError(absl::StrCat(
        name, ":1:", column, ": neighbouring markers are ", Metres(pitch),
        " apart along x (median over the recording, ", pair, "); ", expected,
        ": positions must be in metres, and these look like ", unit));
  }
  if (pitch < -0.25 * robot.marker_pitch_m)
    return absl::InvalidArgumentError(absl::StrCat(
        name, ":1:", column, ": m", next.marker, " is ", Metres(-pitch),
        " per marker behind m", rear.marker, " along x (median over the recording, ", pair,
        "); x must point forward and m1 be the rear marker: the x axis looks reversed, or the "
        "markers are numbered from the front"));
  return absl::OkStatus();
}

}  // namespace gaitforge::recording::internal
