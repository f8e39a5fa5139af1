// The parser's frame check of marker positions (docs/recording-format.md, "Frame and
// units"): a caterpillar recording in millimetres or centimetres, or with x pointing
// backwards, is refused at its header column with what to do; metres in the canonical frame
// pass, with any subset of markers, occlusions and a lab origin anywhere.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "services/recording/recording.h"

namespace gaitforge::recording {
namespace {

const char kSidecar[] =
    "{\"robot\": \"caterpillar\", \"command\": {\"kind\": \"gait\", \"genes\": "
    "[0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.35, 0.45, 0.55, 0.65, 0.75, 0.85, 0.8]}}";

// A crawling caterpillar: markers 0.032 m apart along x at rest, a stroke stretching
// neighbours by up to 11 mm, travel of 3 cm per 0.8 s, hops of 2 mm; positions times
// `scale`, x times `x_sign`, shifted to a lab origin. `markers` lists which of m1..m6 appear.
// With `heading_deg` (not NAN) the robot walks at that angle to x in the x-y plane, and
// the y columns are written too unless `write_y` is false.
std::string Crawl(double scale, double x_sign, const std::vector<int>& markers,
                  double origin_x = 1.7, double origin_z = 0.76, double heading_deg = NAN,
                  bool write_y = true) {
  const bool turned = std::isfinite(heading_deg), with_y = turned && write_y;
  const double c = turned ? std::cos(heading_deg * M_PI / 180) : 1.0;
  const double s = turned ? std::sin(heading_deg * M_PI / 180) : 0.0;
  std::string csv = "t";
  for (int m : markers) {
    const std::string n = ",m" + std::to_string(m);
    csv += n + ".x" + (with_y ? n + ".y" : "") + n + ".z";
  }
  csv += "\n";
  char buf[64];
  for (int row = 0; row < 300; ++row) {
    const double t = 0.01 * row;
    std::snprintf(buf, sizeof buf, "%.2f", t);
    csv += buf;
    const double phase = std::sin(2 * M_PI * t / 0.8);
    for (int m : markers) {
      const double stretch = (m % 2 == 0 ? 0.011 : 0.0) * (0.5 + 0.5 * phase);
      const double along = 0.0375 * t + 0.032 * (m - 1) + stretch;
      const double x = origin_x + c * along, y = 0.4 + s * along;
      const double z = origin_z + 0.025 + 0.002 * std::max(0.0, phase);
      std::snprintf(buf, sizeof buf, ",%.9g", scale * x_sign * x);
      csv += buf;
      if (with_y) {
        std::snprintf(buf, sizeof buf, ",%.9g", scale * y);
        csv += buf;
      }
      std::snprintf(buf, sizeof buf, ",%.9g", scale * z);
      csv += buf;
    }
    csv += "\n";
  }
  return csv;
}

std::string ErrorOf(const std::string& csv) {
  auto r = ParseRecording(csv, kSidecar, "walk.csv", "walk.csv.json");
  return r.ok() ? "OK" : std::string(r.status().message());
}

TEST(MarkerFrameTest, MetresInTheCanonicalFramePass) {
  EXPECT_EQ(ErrorOf(Crawl(1, 1, {1, 2, 3, 4, 5, 6})), "OK");
  EXPECT_EQ(ErrorOf(Crawl(1, 1, {1, 3, 6})), "OK");  // per marker step, not per neighbour
  EXPECT_EQ(ErrorOf(Crawl(1, 1, {4})), "OK");        // one marker: nothing to compare
  EXPECT_EQ(ErrorOf(Crawl(1, 1, {2, 5}, -3.0, 0)), "OK");
  EXPECT_EQ(ErrorOf(Crawl(10, 1, {1, 2, 3, 4, 5, 6})), "OK");  // a robot ten times larger
}

TEST(MarkerFrameTest, MillimetresAndCentimetresAreRefusedWithTheFactor) {
  EXPECT_EQ(ErrorOf(Crawl(1000, 1, {1, 2, 3, 4, 5, 6})),
            "walk.csv:1:4: neighbouring markers are 37.9 m apart along x (median over the "
            "recording, m1.x and m2.x); the caterpillar's neighbouring markers are about "
            "0.032 m apart: positions must be in metres, and these look like millimetres "
            "(divide every position by 1000)");
  const std::string cm = ErrorOf(Crawl(100, 1, {1, 3, 6}));
  EXPECT_NE(cm.find("walk.csv:1:4: "), std::string::npos) << cm;
  EXPECT_NE(cm.find("m1.x and m3.x"), std::string::npos) << cm;
  EXPECT_NE(cm.find("centimetres (divide every position by 100)"), std::string::npos) << cm;
}

TEST(MarkerFrameTest, AReversedXAxisIsRefused) {
  EXPECT_EQ(ErrorOf(Crawl(1, -1, {1, 2, 3, 4, 5, 6})),
            "walk.csv:1:4: m2 is 0.0379 m per marker behind m1 along x (median over the "
            "recording, m1.x and m2.x); x must point forward and m1 be the rear marker: the "
            "x axis looks reversed, or the markers are numbered from the front");
}

TEST(MarkerFrameTest, AFrameTurnedAboutZIsRefusedWithTheAngle) {
  // A lab frame a few degrees off passes; 30 degrees names the turn to undo.
  EXPECT_EQ(ErrorOf(Crawl(1, 1, {1, 2, 3, 4, 5, 6}, 1.7, 0.76, 0)), "OK");
  EXPECT_EQ(ErrorOf(Crawl(1, 1, {1, 2, 3, 4, 5, 6}, 1.7, 0.76, 5)), "OK");
  EXPECT_EQ(ErrorOf(Crawl(1, 1, {1, 2, 3, 4, 5, 6}, 1.7, 0.76, 30)),
            "walk.csv:1:5: the markers lie at 30 degrees from x in the x-y plane (per marker "
            "step 0.0328 m along x and 0.019 m along y, median over the recording, m1.x and "
            "m2.x and their y); x must point along the robot, from m1 (the rear) forward: "
            "rotate the positions by -30 degrees about z");
  // Walking along y: the x spacing alone is nothing; with y, the angle.
  const std::string along_y = ErrorOf(Crawl(1, 1, {1, 3, 6}, 1.7, 0.76, 90));
  EXPECT_NE(along_y.find("the markers lie at 90 degrees from x"), std::string::npos) << along_y;
  EXPECT_NE(along_y.find("rotate the positions by -90 degrees about z"), std::string::npos)
      << along_y;
  // The same recording without its y columns.
  const std::string no_y = Crawl(1, 1, {1, 3, 6}, 1.7, 0.76, 90, false);
  ASSERT_EQ(no_y.substr(0, no_y.find('\n')), "t,m1.x,m1.z,m3.x,m3.z,m6.x,m6.z");
  EXPECT_EQ(ErrorOf(no_y),
            "walk.csv:1:4: neighbouring markers are only 0 m apart along x (median "
            "over the recording, m1.x and m3.x); the caterpillar's neighbouring markers are "
            "about 0.032 m apart: x must point along the robot, from m1 (the rear) forward, "
            "and z up; if the lab's frame is turned about z, include the y columns and the "
            "message says by how much");
  // Millimetres turned by 90 degrees are still millimetres.
  const std::string mm = ErrorOf(Crawl(1000, 1, {1, 2, 3}, 1.7, 0.76, 90));
  EXPECT_NE(mm.find("apart along x and y"), std::string::npos) << mm;
  EXPECT_NE(mm.find("millimetres"), std::string::npos) << mm;
}

TEST(MarkerFrameTest, OcclusionsDoNotFoolTheMedian) {
  // m2 hidden for a third of the recording: its cells empty, bridged, and still metres.
  const std::string full = Crawl(1, 1, {1, 2, 3});
  std::string csv;
  size_t start = 0;
  for (int line = 1; start < full.size(); ++line) {
    const size_t end = full.find('\n', start);
    std::string row = full.substr(start, end - start);
    if (line > 100 && line <= 200) {  // fields: t, m1.x, m1.z, m2.x, ...
      const size_t a = row.find(',', row.find(',', row.find(',') + 1) + 1);
      row.erase(a + 1, row.find(',', a + 1) - a - 1);
    }
    csv += row + "\n";
    start = end + 1;
  }
  ASSERT_NE(csv.find(",,"), std::string::npos);
  EXPECT_EQ(ErrorOf(csv), "OK");
}

}  // namespace
}  // namespace gaitforge::recording
