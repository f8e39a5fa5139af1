// Robust evaluation of the caterpillar (docs/objectives.md, "Robust evaluation"): the
// ensemble runs the real ODE model once per member; its first member (the model as it is,
// start phase 0) is the paper's evaluation bit for bit, and the result does not depend on
// the thread that computes it.
#include <thread>
#include <vector>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "workers/models/caterpillar/caterpillar_objective.h"
#include "workers/models/caterpillar/caterpillar_params.h"
#include "workers/models/caterpillar/gait.h"
#include "workers/objectives/ensemble.h"

namespace gaitforge::caterpillar {
namespace {

using ::testing::HasSubstr;

objectives::EvalInput Wave() {
  objectives::EvalInput in;
  in.genes = TravellingWaveGenes(0.8);
  in.params = {{"cycles", 1}, {"settle_cycles", 1}};
  return in;
}

objectives::EnsembleSpec Ensemble() {
  objectives::EnsembleSpec s;
  s.members = 4;
  s.numerics = {"", "simulation.timestep_s=0.0005"};
  s.start_phases = 2;
  s.parameters = {{"actuators.force_n", 8, 9.5}};
  s.seed = 5;
  return s;
}

TEST(CaterpillarRobust, StartPhaseZeroIsThePapersEvaluationAndOtherPhasesDiffer) {
  const CaterpillarObjective objective(DefaultCaterpillarParams());
  objectives::EvalInput in = Wave();
  const auto plain = objective.Evaluate(in);
  in.params["start_phase"] = 0;
  const auto zero = objective.Evaluate(in);
  in.params["start_phase"] = 0.5;
  const auto half = objective.Evaluate(in);
  ASSERT_TRUE(plain.valid && half.valid);
  EXPECT_EQ(plain.fitness, zero.fitness);  // bit for bit
  EXPECT_NE(plain.fitness, half.fitness);
  in.params["start_phase"] = 1.5;
  EXPECT_THAT(objective.Evaluate(in).reason, HasSubstr("start_phase = 1.5 is outside [0, 1]"));
}

TEST(CaterpillarRobust, TheEnsembleRunsEachMemberOnTheModelAndIgnoresTheThread) {
  const CaterpillarObjective objective(DefaultCaterpillarParams());
  objectives::EnsembleSpec nominal = Ensemble();
  nominal.parameters.clear();
  const auto r = objectives::EvaluateEnsemble(objective, Wave(), nominal);
  ASSERT_TRUE(r.valid) << r.reason;
  EXPECT_EQ(r.metrics.at("member.0"), objective.Evaluate(Wave()).fitness);
  EXPECT_EQ(r.metrics.at("robust.members"), 4);
  EXPECT_DOUBLE_EQ(r.fitness, (r.metrics.at("member.0") + r.metrics.at("member.1") +
                               r.metrics.at("member.2") + r.metrics.at("member.3")) / 4);
  // With parameter samples, in two threads at once: the same numbers.
  objectives::EvalResult a, b;
  std::thread t1([&] { a = objectives::EvaluateEnsemble(objective, Wave(), Ensemble()); });
  std::thread t2([&] { b = objectives::EvaluateEnsemble(objective, Wave(), Ensemble()); });
  t1.join();
  t2.join();
  ASSERT_TRUE(a.valid) << a.reason;
  EXPECT_EQ(a.fitness, b.fitness);
  EXPECT_EQ(a.metrics, b.metrics);
  EXPECT_NE(a.metrics.at("member.0"), r.metrics.at("member.0"));  // the force was sampled
}

}  // namespace
}  // namespace gaitforge::caterpillar
