// Damping as a fraction of critical (caterpillar.yaml links.*_damping_ratio): two free lumps
// joined by one link, set vibrating, must show the target ratio in the logarithmic decrement
// of successive peaks, zeta = delta / sqrt(4 pi^2 + delta^2). The paper's critical damping
// leaves no peaks to measure, so the test lowers the ratio to 0.1 and 0.3; the same formula
// sets the critical value. Tolerance: 5% of the target (ode-notes.md measured 0.099 for 0.10
// with this integration; a fully implicit spring would give about 0.146).
#include <cmath>
#include <vector>

#include "tests/unit/caterpillar/test_helpers.h"
#include "workers/models/caterpillar/param_overrides.h"

namespace gaitforge::caterpillar::testing {
namespace {

// Peak values of a sampled signal, refined by a parabola through each local maximum.
std::vector<double> Peaks(const std::vector<double>& x) {
  std::vector<double> peaks;
  for (size_t i = 1; i + 1 < x.size(); ++i) {
    if (x[i] > x[i - 1] && x[i] >= x[i + 1] && x[i] > 0) {
      const double a = x[i - 1], b = x[i], c = x[i + 1];
      const double denom = a - 2 * b + c;
      peaks.push_back(denom < 0 ? b - (a - c) * (a - c) / (8 * denom) : b);
    }
  }
  return peaks;
}

double MeasuredRatio(const std::vector<double>& signal) {
  const std::vector<double> peaks = Peaks(signal);
  EXPECT_GE(peaks.size(), 3u);
  if (peaks.size() < 3) return NAN;
  const double delta = std::log(peaks[0] / peaks[2]) / 2;  // mean over two periods
  return delta / std::sqrt(4 * M_PI * M_PI + delta * delta);
}

struct Case {
  int first_lump;  // 1: flexure link (1,2); 2: segment link (2,3)
  double ratio;
};

class CaterpillarDamping : public ::testing::TestWithParam<Case> {};

TEST_P(CaterpillarDamping, AxialLogDecrementMatchesTarget) {
  CaterpillarParams p = Params();
  p.links.axial_damping_ratio = GetParam().ratio;
  CaterpillarSim sim(p, FreeChain(GetParam().first_lump, GetParam().first_lump + 1));
  dBodySetLinearVel(sim.body().lump(0), -0.05, 0, 0);
  dBodySetLinearVel(sim.body().lump(1), 0.05, 0, 0);
  std::vector<double> stretch;
  Simulate(sim, 0.2, 0, nullptr, [&](CaterpillarSim& s) { stretch.push_back(s.body().LinkExtension(0)); });
  EXPECT_NEAR(MeasuredRatio(stretch), GetParam().ratio, 0.05 * GetParam().ratio);
}

TEST_P(CaterpillarDamping, BendingLogDecrementMatchesTarget) {
  CaterpillarParams p = Params();
  p.links.bending_damping_ratio = GetParam().ratio;
  CaterpillarSim sim(p, FreeChain(GetParam().first_lump, GetParam().first_lump + 1));
  // Opposite spins about the centres: the joint point moves the same way on both lumps, so
  // the start is consistent with the link and excites pure bending.
  dBodySetAngularVel(sim.body().lump(0), 0, -2, 0);
  dBodySetAngularVel(sim.body().lump(1), 0, 2, 0);
  std::vector<double> bend;
  Simulate(sim, 0.2, 0, nullptr, [&](CaterpillarSim& s) { bend.push_back(s.body().LinkBend(0)); });
  EXPECT_NEAR(MeasuredRatio(bend), GetParam().ratio, 0.05 * GetParam().ratio);
}

// The catalog's damping.scale (scale.link_damping) multiplies both ratios: from the paper's
// critical damping, a factor of 0.2 must show as zeta 0.2 in the axial and bending decrements
// of a flexure link, and a factor that leaves a ratio outside [0.01, 10] is refused with
// the field named.
TEST(CaterpillarDampingScale, ScalesBothRatiosAndTheirDecrements) {
  CaterpillarParams p = Params();
  ASSERT_EQ(p.links.axial_damping_ratio, 1.0);
  ASSERT_TRUE(SetParam(p, "scale.link_damping", 0.2).ok());
  EXPECT_DOUBLE_EQ(p.links.axial_damping_ratio, 0.2);
  EXPECT_DOUBLE_EQ(p.links.bending_damping_ratio, 0.2);
  EXPECT_EQ(p.links.flexure.axial_n_per_m, Params().links.flexure.axial_n_per_m);
  {
    CaterpillarSim sim(p, FreeChain(1, 2));
    dBodySetLinearVel(sim.body().lump(0), -0.05, 0, 0);
    dBodySetLinearVel(sim.body().lump(1), 0.05, 0, 0);
    std::vector<double> stretch;
    Simulate(sim, 0.2, 0, nullptr,
             [&](CaterpillarSim& s) { stretch.push_back(s.body().LinkExtension(0)); });
    EXPECT_NEAR(MeasuredRatio(stretch), 0.2, 0.01);
  }
  {
    CaterpillarSim sim(p, FreeChain(1, 2));
    dBodySetAngularVel(sim.body().lump(0), 0, -2, 0);
    dBodySetAngularVel(sim.body().lump(1), 0, 2, 0);
    std::vector<double> bend;
    Simulate(sim, 0.2, 0, nullptr,
             [&](CaterpillarSim& s) { bend.push_back(s.body().LinkBend(0)); });
    EXPECT_NEAR(MeasuredRatio(bend), 0.2, 0.01);
  }
  CaterpillarParams q = Params();
  const absl::Status s = SetParam(q, "scale.link_damping", 20);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(std::string(s.message()).find("links.axial_damping_ratio"), std::string::npos) << s;
  EXPECT_EQ(q.links.axial_damping_ratio, 1.0);  // unchanged on error
}

INSTANTIATE_TEST_SUITE_P(Links, CaterpillarDamping,
                         ::testing::Values(Case{1, 0.1}, Case{2, 0.1}, Case{1, 0.3}, Case{2, 0.3}),
                         [](const auto& info) {
                           return std::string(info.param.first_lump == 1 ? "Flexure" : "Segment") +
                                  (info.param.ratio < 0.2 ? "Zeta010" : "Zeta030");
                         });

}  // namespace
}  // namespace gaitforge::caterpillar::testing
