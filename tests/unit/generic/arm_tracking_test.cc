// Paper 004's tracking (workers/models/generic/generic_tracking.h) on its continuum arm: a
// path the arm itself made under known rod forces is followed closely with the feed-forward
// learned on an exact model, poorly by the PID alone, and worse with the feed-forward of a
// model that lacks the plant's softening than with one that has it.
#include <cmath>
#include <string>
#include <vector>

#include "gtest/gtest.h"
#include "robots/registry.h"
#include "workers/models/generic/generic_tracking.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::generic {
namespace {

const robots::RobotDescriptor& Arm() { return robots::Robot("continuum_arm"); }

// The tip's x and y every 20 ms over 6 s from rest under rod forces turning around the arm
// (1.2 N, eased in over 2 s): a path the arm can follow, starting where it rests.
Path MadePath() {
  ParamValues v(Arm());
  auto w = GenericWorld::Build(Arm(), v, 0);
  EXPECT_TRUE(w.ok());
  Path p;
  p.axes.resize(2);
  const double h = (*w)->timestep();
  for (int i = 0; i <= std::lround(6.0 / h); ++i) {
    const double t = i * h;
    if (i % std::lround(0.02 / h) == 0) {
      p.t.push_back(t);
      p.axes[0].push_back(*(*w)->Channel("tip.x"));
      p.axes[1].push_back(*(*w)->Channel("tip.y"));
    }
    const double ease = t < 2 ? 0.5 * (1 - std::cos(M_PI * t / 2)) : 1.0;
    std::vector<double> f;
    for (int k = 0; k < 3; ++k) f.push_back(1.2 * ease * std::cos(2 * M_PI * t / 6 + 2.0944 * k));
    EXPECT_TRUE((*w)->Step(f).ok);
  }
  return p;
}

ParamValues With(const std::string& name, double value) {
  ParamValues v(Arm());
  EXPECT_TRUE(v.Set(name, value).ok()) << name;
  return v;
}

class ArmTrackingTest : public ::testing::Test {
 protected:
  void SetUp() override { sim::InitThread(); }
};

TEST_F(ArmTrackingTest, TheExactModelsFeedForwardTracksWhereThePidAloneLags) {
  const Path path = MadePath();
  const ParamValues arm(Arm());
  auto ff = LearnFeedForward(Arm(), arm, path, 15, {});
  ASSERT_TRUE(ff.ok()) << ff.status();
  EXPECT_EQ(ff->iterations, 15);
  EXPECT_LT(ff->residual_rms_m, 1e-4);  // the model follows its own feed-forward
  const TrackingResult pid = Track(Arm(), arm, path, nullptr, {});
  const TrackingResult both = Track(Arm(), arm, path, &*ff, {});
  ASSERT_TRUE(pid.valid && both.valid) << pid.reason << both.reason;
  EXPECT_GT(pid.max_error_m, 0.02);  // the path moves the tip by about 5 cm
  EXPECT_LT(both.rms_error_m, 0.1 * pid.rms_error_m);
  EXPECT_LT(both.iste, pid.iste);
  // Ticks at 50 Hz over the lead-in (2 s) and the path (6 s), both ends included.
  EXPECT_EQ(pid.t.size(), 401u);
  EXPECT_DOUBLE_EQ(pid.t.front(), -2.0);
}

TEST_F(ArmTrackingTest, AModelWithThePlantsSofteningFeedsForwardBetterThanOneWithout) {
  const Path path = MadePath();
  const ParamValues plant = With("effect.joint_softening_per_rad", 3);
  auto constant = LearnFeedForward(Arm(), ParamValues(Arm()), path, 15, {});
  auto matched = LearnFeedForward(Arm(), plant, path, 15, {});
  ASSERT_TRUE(constant.ok() && matched.ok());
  const TrackingResult with_constant = Track(Arm(), plant, path, &*constant, {});
  const TrackingResult with_matched = Track(Arm(), plant, path, &*matched, {});
  ASSERT_TRUE(with_constant.valid && with_matched.valid);
  EXPECT_LT(with_matched.max_error_m, 0.5 * with_constant.max_error_m)
      << with_matched.max_error_m << " vs " << with_constant.max_error_m;
}

TEST_F(ArmTrackingTest, ARateThatIsNotWholeTimestepsIsRefusedWithTheReason) {
  const TrackingResult r = Track(Arm(), With("tracking.rate_hz", 30), MadePath(), nullptr, {});
  EXPECT_FALSE(r.valid);
  EXPECT_NE(r.reason.find("tracking.rate_hz 30 Hz is not a whole number of 0.001 s timesteps"),
            std::string::npos)
      << r.reason;
}

TEST_F(ArmTrackingTest, APathNeedsTheTrackedMarkersColumns) {
  recording::Recording rec;
  rec.channels = {"tip.x"};
  rec.t = {0, 0.02};
  rec.columns = {{0, 0}};
  auto p = PathOf(Arm(), rec, "loop.csv");
  ASSERT_FALSE(p.ok());
  EXPECT_NE(std::string(p.status().message()).find("loop.csv: no column 'tip.y'"), std::string::npos)
      << p.status();
  EXPECT_FALSE(PathOf(robots::Robot("caterpillar"), rec, "loop.csv").ok());
}

}  // namespace
}  // namespace gaitforge::generic
