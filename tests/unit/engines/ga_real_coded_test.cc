// Paper 004's real-coded GA (ga_engine.h: selection tournament, crossover blend, mutation
// gaussian) and the stop rule (stop_fitness): the operators keep genes in range, prefer
// better members, converge where paper 000's operators stall, and a study stopped by
// stop_fitness resumes stopped.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "services/engines/ga/ga_engine.h"
#include "services/engines/ga/ga_operators.h"

namespace gaitforge::engines::ga {
namespace {

Bounds Box(int n, double lo, double hi) {
  Bounds b;
  b.lo.assign(n, lo);
  b.hi.assign(n, hi);
  return b;
}

GaConfig RealCoded(uint64_t seed, int gens) {
  GaConfig c;
  c.seed = seed;
  c.population = 60;
  c.generations = gens;
  c.elite = 2;
  c.bounds = Box(4, 0, 1);
  c.selection = "tournament";
  c.crossover = "blend";
  c.mutation = "gaussian";
  return c;
}

// Fitness -sum (x - target)^2, the optimum inside the box.
std::vector<Evaluation> Score(const std::vector<Candidate>& cands) {
  const double target[] = {0.15, 0.8, 0.3, 0.55};
  std::vector<Evaluation> out;
  for (const auto& c : cands) {
    double f = 0;
    for (size_t i = 0; i < c.genes.size(); ++i) f -= (c.genes[i] - target[i]) * (c.genes[i] - target[i]);
    out.push_back({true, f, ""});
  }
  return out;
}

double Best(GaEngine& ga) {
  while (!ga.Done()) EXPECT_TRUE(ga.Tell(Score(ga.Ask())).ok());
  return ga.HallOfFame().front().eval.fitness;
}

TEST(GaOperators, TournamentPrefersTheBetterAndKeepsDrawsInRange) {
  std::vector<Evaluation> evals;
  for (int m = 0; m < 10; ++m) evals.push_back({true, static_cast<double>(m), ""});
  int wins_of_best = 0;
  for (uint64_t k = 0; k < 2000; ++k) {
    core::KeyedRng rng(1, 1, k, core::Purpose::kSelect);
    const int pick = TournamentSelect(evals, 3, rng);
    ASSERT_GE(pick, 0);
    ASSERT_LT(pick, 10);
    wins_of_best += pick == 9;
  }
  // P(best in 3 draws of 10) = 1 - 0.9^3 = 0.271.
  EXPECT_NEAR(wins_of_best / 2000.0, 0.271, 0.03);
}

TEST(GaOperators, BlendStaysInRangeAndAroundTheParents) {
  const Bounds b = Box(3, 0, 1);
  for (uint64_t k = 0; k < 500; ++k) {
    std::vector<double> x = {0.2, 0.9, 0.5}, y = {0.4, 0.99, 0.5};
    core::KeyedRng rng(2, 1, k, core::Purpose::kCrossover);
    BlendCrossover(x, y, b, 1.0, 0.5, rng);
    for (const auto* v : {&x, &y}) {
      EXPECT_GE((*v)[0], 0.1);  // [0.2 - 0.1, 0.4 + 0.1]
      EXPECT_LE((*v)[0], 0.5);
      EXPECT_GE((*v)[1], 0.855);
      EXPECT_LE((*v)[1], 1.0);  // clamped at hi
      EXPECT_EQ((*v)[2], 0.5);  // equal parents: nothing to blend
    }
  }
  std::vector<double> x = {0.2}, y = {0.4};
  core::KeyedRng rng(2, 1, 0, core::Purpose::kCrossover);
  BlendCrossover(x, y, Box(1, 0, 1), 0.0, 0.5, rng);  // rate 0: the parents
  EXPECT_EQ(x[0], 0.2);
  EXPECT_EQ(y[0], 0.4);
}

TEST(GaOperators, GaussianMutationStepsAreATenthOfTheRange) {
  const Bounds b = Box(1, -10, 10);
  double sum2 = 0;
  const int n = 4000;
  for (int k = 0; k < n; ++k) {
    std::vector<double> g = {0.0};
    core::KeyedRng rng(3, 1, k, core::Purpose::kMutate);
    EXPECT_EQ(MutateGaussian(g, b, 1.0, 0.1, rng), 1);
    sum2 += g[0] * g[0];
  }
  EXPECT_NEAR(std::sqrt(sum2 / n), 2.0, 0.1);  // sd 0.1 x 20
}

TEST(GaEngine, RealCodedConvergesWherePaper000sOperatorsStall) {
  auto real = GaEngine::Create(RealCoded(7, 40));
  ASSERT_TRUE(real.ok()) << real.status();
  GaConfig paper000 = RealCoded(7, 40);
  paper000.selection = "roulette";
  paper000.crossover = "one_point";
  paper000.mutation = "reinit";
  auto old = GaEngine::Create(paper000);
  ASSERT_TRUE(old.ok());
  const double real_best = Best(**real), old_best = Best(**old);
  EXPECT_GT(real_best, -1e-4);
  EXPECT_GT(real_best, old_best);
}

TEST(GaEngine, StopFitnessEndsTheStudyAndSurvivesAResume) {
  GaConfig c = RealCoded(9, 200);
  c.stop_fitness = -1e-3;
  auto a = GaEngine::Create(c);
  ASSERT_TRUE(a.ok());
  int generations = 0;
  while (!(*a)->Done()) {
    ASSERT_TRUE((*a)->Tell(Score((*a)->Ask())).ok());
    ++generations;
  }
  EXPECT_LT(generations, 200);
  EXPECT_GE((*a)->HallOfFame().front().eval.fitness, -1e-3);
  EXPECT_NE((*a)->StopReason().find("stop_fitness"), std::string::npos);
  auto b = GaEngine::Create(c);
  ASSERT_TRUE(b.ok());
  ASSERT_TRUE((*b)->LoadState((*a)->SaveState()).ok());
  EXPECT_TRUE((*b)->Done());
  EXPECT_EQ((*b)->generation(), generations);
}

TEST(GaConfig, RefusesUnknownOperatorsByName) {
  GaConfig c = RealCoded(1, 2);
  c.crossover = "two_point";
  EXPECT_EQ(ValidateGaConfig(c).message(), "ga.crossover = 'two_point' is not one of one_point, blend");
  c = RealCoded(1, 2);
  c.stop_fitness = std::nan("");
  EXPECT_FALSE(ValidateGaConfig(c).ok());
}

}  // namespace
}  // namespace gaitforge::engines::ga
