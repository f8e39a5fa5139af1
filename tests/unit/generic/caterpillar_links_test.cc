// The caterpillar's spring links on the generic builder (joint type spring_link), on rigs
// cut from its descriptor (caterpillar_rig.h).
//
// Statics: under an axial load F each link stretches F/k, under a bending moment tau each
// bends tau/kappa (the paper's FEA stiffnesses). The spring is the soft row
// f = -k x_n - c v_{n+1}, exact at rest, so the tolerance is 0.5% (the remainder is the
// unfinished decay of the chain's slow, overdamped bending mode: 0.75% left after 1 s,
// 0.005% after 2 s; the tests run 3 s).
//
// Damping as a fraction of critical (links.*_damping_ratio): two free lumps joined by one
// link, set vibrating, must show the target ratio in the logarithmic decrement of
// successive peaks, zeta = delta / sqrt(4 pi^2 + delta^2). The paper's critical damping
// leaves no peaks to measure, so the test lowers the ratio to 0.1 and 0.3; the same formula
// sets the critical value. Tolerance: 5% of the target (ode-notes.md measured 0.099 for
// 0.10 with this integration; a fully implicit spring would give about 0.146).
#include <cmath>
#include <string>
#include <vector>

#include "tests/unit/generic/caterpillar_rig.h"

namespace gaitforge::generic::testing {
namespace {

constexpr double kRelTol = 0.005;

double AxialStiffness(const Rig& rig, int joint) {
  return rig.Value(*rig.d->joints[joint].axial_stiffness);
}

TEST(CaterpillarStatics, AxialDeflectionIsLoadOverStiffness) {
  Rig rig = MakeRig(FreeChain());
  const double force = 0.1;  // N, the paper's FEA axial load
  Simulate(rig, 3.0, 0, [&](Rig& r) {
    dBodyAddForce(r->ode_body(0), -force, 0, 0);
    dBodyAddForce(r->ode_body(5), force, 0, 0);
  });
  for (int k = 0; k < 5; ++k) {
    const double stretch =
        rig->BodyCentre(k + 1)[0] - rig->BodyCentre(k)[0] - rig("lumps.spacing_m");
    const double expected = force / AxialStiffness(rig, k);
    EXPECT_NEAR(stretch, expected, kRelTol * expected) << "link " << k + 1;
    EXPECT_NEAR(rig->LinkExtension(k), expected, kRelTol * expected) << "link " << k + 1;
  }
}

TEST(CaterpillarStatics, BendingDeflectionIsMomentOverStiffness) {
  Rig rig = MakeRig(FreeChain());
  const double moment = 0.005;  // N m about +y: a pure moment through the whole chain
  Simulate(rig, 3.0, 0, [&](Rig& r) {
    dBodyAddTorque(r->ode_body(0), 0, -moment, 0);
    dBodyAddTorque(r->ode_body(5), 0, moment, 0);
  });
  for (int k = 0; k < 5; ++k) {
    const double bend = Pitch(rig->ode_body(k + 1)) - Pitch(rig->ode_body(k));
    const double expected = moment / rig.Value(*rig.d->joints[k].stiffness);
    EXPECT_NEAR(bend, expected, kRelTol * expected) << "link " << k + 1;
    EXPECT_NEAR(rig->LinkBend(k), expected, kRelTol * expected) << "link " << k + 1;
    // No axial load: the links keep their length.
    EXPECT_NEAR(rig->LinkExtension(k), 0, 1e-6) << "link " << k + 1;
  }
}

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

// A pair of lumps pulled apart (axial) or spun against each other (bending), free; the
// link's stretch or bend over 0.2 s.
std::vector<double> Ring(Rig& rig, bool axial) {
  if (axial) {
    dBodySetLinearVel(rig->ode_body(0), -0.05, 0, 0);
    dBodySetLinearVel(rig->ode_body(1), 0.05, 0, 0);
  } else {
    // Opposite spins about the centres: the joint point moves the same way on both lumps,
    // so the start is consistent with the link and excites pure bending.
    dBodySetAngularVel(rig->ode_body(0), 0, -2, 0);
    dBodySetAngularVel(rig->ode_body(1), 0, 2, 0);
  }
  std::vector<double> signal;
  Simulate(rig, 0.2, 0, nullptr, [&](Rig& r) {
    signal.push_back(axial ? r->LinkExtension(0) : r->LinkBend(0));
  });
  return signal;
}

struct Case {
  int first_lump;  // 1: flexure link (1,2); 2: segment link (2,3)
  double ratio;
};

class CaterpillarDamping : public ::testing::TestWithParam<Case> {};

TEST_P(CaterpillarDamping, AxialLogDecrementMatchesTarget) {
  const Case c = GetParam();
  Rig rig = MakeRig(FreeChain(c.first_lump, c.first_lump + 1), {{"links.axial_damping_ratio", c.ratio}});
  EXPECT_NEAR(MeasuredRatio(Ring(rig, true)), c.ratio, 0.05 * c.ratio);
}

TEST_P(CaterpillarDamping, BendingLogDecrementMatchesTarget) {
  const Case c = GetParam();
  Rig rig = MakeRig(FreeChain(c.first_lump, c.first_lump + 1), {{"links.bending_damping_ratio", c.ratio}});
  EXPECT_NEAR(MeasuredRatio(Ring(rig, false)), c.ratio, 0.05 * c.ratio);
}

INSTANTIATE_TEST_SUITE_P(Links, CaterpillarDamping,
                         ::testing::Values(Case{1, 0.1}, Case{2, 0.1}, Case{1, 0.3}, Case{2, 0.3}),
                         [](const auto& info) {
                           return std::string(info.param.first_lump == 1 ? "Flexure" : "Segment") +
                                  (info.param.ratio < 0.2 ? "Zeta010" : "Zeta030");
                         });

// The descriptor's scale.link_damping multiplies both ratios: from the paper's critical
// damping, a factor of 0.2 must show as zeta 0.2 in the axial and bending decrements of a
// flexure link, and a factor that leaves a ratio outside [0.01, 10] is refused with the
// field named and nothing changed.
TEST(CaterpillarDampingScale, ScalesBothRatiosAndTheirDecrements) {
  Rig axial = MakeRig(FreeChain(1, 2), {{"scale.link_damping", 0.2}});
  EXPECT_DOUBLE_EQ(axial("links.axial_damping_ratio"), 0.2);
  EXPECT_DOUBLE_EQ(axial("links.bending_damping_ratio"), 0.2);
  EXPECT_EQ(axial("links.flexure.axial_stiffness_n_per_m"), 1040);
  EXPECT_NEAR(MeasuredRatio(Ring(axial, true)), 0.2, 0.01);
  Rig bending = MakeRig(FreeChain(1, 2), {{"scale.link_damping", 0.2}});
  EXPECT_NEAR(MeasuredRatio(Ring(bending, false)), 0.2, 0.01);

  ParamValues q(robots::Robot("caterpillar"));
  const absl::Status s = q.Set("scale.link_damping", 20);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(std::string(s.message()).find("links.axial_damping_ratio"), std::string::npos) << s;
  EXPECT_EQ(q("links.axial_damping_ratio"), 1.0);  // unchanged on error
}

}  // namespace
}  // namespace gaitforge::generic::testing
