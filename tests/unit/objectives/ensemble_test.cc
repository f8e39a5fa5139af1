// Robust evaluation's ensemble (workers/objectives/ensemble.h): its members depend only on
// the spec and its seed, the parameter samples are stratified, the statistics are the
// documented ones, and a gait that does well on one numeric variant only ranks below one
// that does fairly on all.
#include "workers/objectives/ensemble.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

namespace gaitforge::objectives {
namespace {

using ::testing::HasSubstr;

EnsembleSpec Spec() {
  EnsembleSpec s;
  s.members = 8;
  s.numerics = {"", "simulation.timestep_s=0.0005"};
  s.start_phases = 2;
  s.parameters = {{"actuators.force_n", 8, 10}, {"scale.mass", 0.9, 1.1}};
  s.seed = 42;
  return s;
}

TEST(Ensemble, MembersCycleNumericsThenStartPhases) {
  const auto m = Members(Spec());
  ASSERT_EQ(m.size(), 8u);
  for (int i = 0; i < 8; ++i) {
    EXPECT_EQ(m[i].numeric, Spec().numerics[i % 2]);
    EXPECT_EQ(m[i].start_phase, ((i / 2) % 2) * 0.5);
  }
  EXPECT_THAT(m[1].SetText(Spec()), HasSubstr("simulation.timestep_s=0.0005,actuators.force_n="));
}

TEST(Ensemble, EachParameterUsesEveryStratumOnceAndDependsOnlyOnTheSeed) {
  const auto a = Members(Spec()), b = Members(Spec());
  for (int j = 0; j < 2; ++j) {
    std::set<int> strata;
    const auto& r = Spec().parameters[j];
    for (size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].values[j], b[i].values[j]);  // bit for bit
      EXPECT_GE(a[i].values[j], r.lo);
      EXPECT_LT(a[i].values[j], r.hi);
      strata.insert(static_cast<int>((a[i].values[j] - r.lo) / (r.hi - r.lo) * 8));
    }
    EXPECT_EQ(strata.size(), 8u);
  }
  EnsembleSpec other = Spec();
  other.seed = 43;
  EXPECT_NE(Members(other)[0].values[0], a[0].values[0]);
}

// Given samples are taken whole (a member's values are one sample's), each once while the
// members do not outnumber them, in an order the seed alone decides.
TEST(Ensemble, GivenSamplesKeepTheirPairsInAnOrderDrawnFromTheSeed) {
  EnsembleSpec s = Spec();
  s.members = 5;
  for (int k = 0; k < 12; ++k) s.samples.push_back({8.0 + 0.1 * k, 0.9 + 0.01 * k});
  const auto a = Members(s), b = Members(s);
  std::set<int> used;
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].values.size(), 2u);
    EXPECT_EQ(a[i].values, b[i].values);
    const int k = static_cast<int>(std::lround((a[i].values[0] - 8.0) / 0.1));
    EXPECT_EQ(a[i].values, s.samples[k]);  // the pair as given
    used.insert(k);
  }
  EXPECT_EQ(used.size(), 5u);
  EnsembleSpec other = s;
  other.seed = 43;
  std::vector<std::vector<double>> first, second;
  for (const auto& m : Members(s)) first.push_back(m.values);
  for (const auto& m : Members(other)) second.push_back(m.values);
  EXPECT_NE(first, second);
  s.members = 30;  // more members than samples: every sample, then again in the same order
  const auto many = Members(s);
  for (int i = 12; i < 30; ++i) EXPECT_EQ(many[i].values, many[i - 12].values);
}

// A range marked log (a calibration's gene searched by its logarithm, spanning decades) is
// stratified in ln x: each decade of [1e-5, 1e-1] holds a quarter of the members, where a
// linear sample would put 90% of them in the top decade.
TEST(Ensemble, ALogRangeIsStratifiedInItsLogarithm) {
  EnsembleSpec s;
  s.members = 16;
  s.parameters = {{"effect.contact_slip_m_per_n_s", 1e-5, 1e-1, true}};
  s.seed = 7;
  std::vector<int> per_decade(4, 0);
  std::set<int> strata;
  for (const EnsembleMember& m : Members(s)) {
    const double x = m.values[0];
    ASSERT_GE(x, 1e-5);
    ASSERT_LE(x, 1e-1);
    const double u = (std::log(x) - std::log(1e-5)) / (std::log(1e-1) - std::log(1e-5));
    strata.insert(std::min(15, static_cast<int>(u * 16)));
    ++per_decade[std::min(3, static_cast<int>(u * 4))];
  }
  EXPECT_EQ(strata.size(), 16u);
  EXPECT_THAT(per_decade, ::testing::ElementsAre(4, 4, 4, 4));
  s.parameters[0].log = false;  // the same stream, linear: most members in the top decade
  int top = 0;
  for (const EnsembleMember& m : Members(s)) top += m.values[0] >= 1e-2;
  EXPECT_GE(top, 14);
}

TEST(Ensemble, StatisticsAreMeanLowerQuantileAndMeanMinusKSd) {
  EnsembleSpec s;
  const std::vector<double> v = {4, 1, 3, 2};
  EXPECT_DOUBLE_EQ(Combine(v, s), 2.5);
  s.statistic = Statistic::kQuantile;
  s.quantile = 0.25;  // position 0.75 between 1 and 2
  EXPECT_DOUBLE_EQ(Combine(v, s), 1.75);
  s.statistic = Statistic::kMeanMinusSd;
  s.k = 2;
  EXPECT_DOUBLE_EQ(Combine(v, s), 2.5 - 2 * std::sqrt(5.0 / 3.0));
  EXPECT_DOUBLE_EQ(Combine({7}, s), 7);  // one member: no spread
}

// A stand-in for a simulator whose numerics matter to one gait: gene 0 selects the gait.
// Gait 0 "hops": 5 cm on the model as it is, -1 cm on any other timestep. Gait 1 "walks":
// 2 cm on every variant. Start phase and set items reach the objective as documented.
class TwoGaits : public Objective {
 public:
  EvalResult Evaluate(const EvalInput& in) const override {
    EvalResult r;
    r.valid = true;
    const bool variant = in.options.count("set") &&
                         in.options.at("set").find("timestep_s") != std::string::npos;
    r.fitness = in.genes[0] == 0 ? (variant ? -0.01 : 0.05) : 0.02;
    r.metrics["simulated_s"] = 1;
    r.metrics["phase"] = in.params.count("start_phase") ? in.params.at("start_phase") : 0;
    return r;
  }
};

TEST(Ensemble, AGaitThatHopsOnOneVariantRanksBelowOneThatWalksOnAll) {
  TwoGaits objective;
  EnsembleSpec s;
  s.members = 4;
  s.numerics = {"", "simulation.timestep_s=0.0005", "simulation.timestep_s=0.00075",
                "simulation.timestep_s=0.00125"};
  EvalInput hop, walk;
  hop.genes = {0};
  walk.genes = {1};
  EXPECT_GT(objective.Evaluate(hop).fitness, objective.Evaluate(walk).fitness);
  const EvalResult h = EvaluateEnsemble(objective, hop, s), w = EvaluateEnsemble(objective, walk, s);
  ASSERT_TRUE(h.valid && w.valid);
  EXPECT_LT(h.fitness, w.fitness);
  EXPECT_DOUBLE_EQ(h.metrics.at("member.0"), 0.05);
  EXPECT_DOUBLE_EQ(h.metrics.at("member.3"), -0.01);
  EXPECT_DOUBLE_EQ(h.metrics.at("simulated_s"), 4);  // summed: the ensemble's cost
  EXPECT_DOUBLE_EQ(h.metrics.at("robust.min"), -0.01);
}

class FailsOnVariant : public TwoGaits {
 public:
  EvalResult Evaluate(const EvalInput& in) const override {
    EvalResult r = TwoGaits::Evaluate(in);
    if (in.params.count("start_phase")) {
      r.valid = false;
      r.reason = "diverged at t = 1 s";
    }
    return r;
  }
};

TEST(Ensemble, AnInvalidMemberMakesTheEvaluationInvalidAndIsNamed) {
  FailsOnVariant objective;
  EnsembleSpec s;
  s.members = 2;
  s.start_phases = 2;
  EvalInput in;
  in.genes = {1};
  in.options["set"] = "actuators.force_n=9";
  const EvalResult r = EvaluateEnsemble(objective, in, s);
  EXPECT_FALSE(r.valid);
  EXPECT_THAT(r.reason, HasSubstr("ensemble member 1 (the model as it is, start phase 0.5): "
                                  "diverged at t = 1 s"));
  EXPECT_EQ(r.metrics.at("robust.invalid_member"), 1);
}

}  // namespace
}  // namespace gaitforge::objectives
