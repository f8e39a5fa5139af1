#include "services/engines/sweep/sweep_engine.h"

#include <cmath>
#include <functional>
#include <vector>

#include <gtest/gtest.h>

#include "bench/cmaes_functions.h"

namespace gaitforge::engines::sweep {
namespace {

using Objective = std::function<double(const std::vector<double>&)>;

SweepConfig RosenbrockConfig(int d, int points, int top_k) {
  SweepConfig c;
  c.bounds.lo.assign(d, -2.0);
  c.bounds.hi.assign(d, 2.0);
  c.points_per_axis = {points};
  c.top_k = top_k;
  c.nm_max_iterations = 2000;
  c.nm_tolerance = 1e-10;
  return c;
}

std::unique_ptr<SweepEngine> Make(const SweepConfig& c) {
  auto e = SweepEngine::Create(c);
  EXPECT_TRUE(e.ok()) << e.status();
  return std::move(*e);
}

std::vector<Evaluation> Evaluate(const std::vector<Candidate>& cands, const Objective& f) {
  std::vector<Evaluation> evals;
  for (const auto& c : cands) evals.push_back({true, -f(c.genes), ""});
  return evals;
}

TEST(SweepConfigTest, ValidationNamesTheField) {
  SweepConfig c = RosenbrockConfig(2, 5, 2);
  EXPECT_TRUE(ValidateSweepConfig(c).ok());
  auto bad = [&](auto mutate, const char* field) {
    SweepConfig b = c;
    mutate(b);
    const absl::Status s = ValidateSweepConfig(b);
    EXPECT_FALSE(s.ok()) << field;
    EXPECT_NE(s.message().find(field), std::string::npos) << s.message();
  };
  bad([](SweepConfig& b) { b.points_per_axis = {3, 3, 3}; }, "sweep.points_per_axis");
  bad([](SweepConfig& b) { b.points_per_axis = {3, 0}; }, "sweep.points_per_axis[1]");
  bad([](SweepConfig& b) { b.top_k = 26; }, "sweep.top_k");
  bad([](SweepConfig& b) { b.nm_max_iterations = -1; }, "sweep.nm_max_iterations");
  bad([](SweepConfig& b) { b.nm_tolerance = -1; }, "sweep.nm_tolerance");
  bad([](SweepConfig& b) { b.max_evaluations = -1; }, "sweep.max_evaluations");
}

TEST(SweepEngineTest, GridCoversFacesAndHoldsSingleAxesAtTheCentre) {
  SweepConfig c;
  c.bounds = {{0, 10, -1}, {1, 20, 1}};
  c.points_per_axis = {3, 1, 2};
  c.top_k = 1;
  auto e = Make(c);
  const auto& grid = e->Ask();
  ASSERT_EQ(grid.size(), 6u);
  EXPECT_EQ(grid[0].genes, (std::vector<double>{0, 15, -1}));
  EXPECT_EQ(grid[1].genes, (std::vector<double>{0, 15, 1}));
  EXPECT_EQ(grid[5].genes, (std::vector<double>{1, 15, 1}));
  EXPECT_EQ(grid[2].genes[0], 0.5);
}

// A factorial design (paper 002's experiment): a factor sets its genes together level by
// level, factors multiply (the first slowest), the other genes take their grid points
// (fastest), and with top_k 0 the grid is the whole study.
TEST(SweepEngineTest, FactorsSetTheirGenesTogetherAndMultiply) {
  SweepConfig c;
  c.bounds = {{0, 0, 0, -1}, {1, 1, 10, 1}};
  c.points_per_axis = {2};
  c.factors = {{{0, 1}, {{0.2, 0.8}, {0.6, 0.1}}},  // "gait": genes 0 and 1 together
               {{2}, {{1}, {2}, {3}}}};             // "speed"
  c.top_k = 0;
  auto e = Make(c);
  const auto grid = e->Ask();
  ASSERT_EQ(grid.size(), 12u);  // 2 gaits x 3 speeds x 2 points of gene 3
  EXPECT_EQ(grid[0].genes, (std::vector<double>{0.2, 0.8, 1, -1}));
  EXPECT_EQ(grid[1].genes, (std::vector<double>{0.2, 0.8, 1, 1}));
  EXPECT_EQ(grid[2].genes, (std::vector<double>{0.2, 0.8, 2, -1}));
  EXPECT_EQ(grid[6].genes, (std::vector<double>{0.6, 0.1, 1, -1}));
  EXPECT_EQ(grid[11].genes, (std::vector<double>{0.6, 0.1, 3, 1}));
  ASSERT_TRUE(e->Tell(Evaluate(grid, [](const std::vector<double>& x) { return x[2]; })).ok());
  EXPECT_TRUE(e->Done());
  EXPECT_EQ(e->StopReason(), "sweep: the grid is done (top_k 0: no local searches)");
  // A level outside a gene's bounds, or a gene in two factors, is refused.
  SweepConfig bad = c;
  bad.factors[1].levels[2] = {11};
  EXPECT_NE(ValidateSweepConfig(bad).message().find("sweep.factors[1]: level 2 puts gene 2 at 11"),
            std::string::npos);
  bad = c;
  bad.factors[1].genes = {1};
  EXPECT_NE(ValidateSweepConfig(bad).message().find("set by two factors"), std::string::npos);
}

// Nelder-Mead from the grid's best point on Rosenbrock in 2 and 3 dimensions. The grid
// (8 points per axis on [-2, 2]) does not contain the optimum (1, ..., 1).
TEST(SweepEngineTest, NelderMeadConvergesOnRosenbrockFromTheBestGridPoint) {
  for (int d : {2, 3}) {
    auto e = Make(RosenbrockConfig(d, 8, 1));
    ASSERT_TRUE(e->Tell(Evaluate(e->Ask(), bench::Rosenbrock)).ok());
    ASSERT_FALSE(e->in_grid());
    const auto grid_best = e->HallOfFame()[0];
    EXPECT_GT(-grid_best.eval.fitness, 0.1);
    ASSERT_EQ(e->searches().size(), 1u);
    EXPECT_EQ(e->searches()[0].best(), grid_best.genes);
    EXPECT_EQ(e->Ask().size(), static_cast<size_t>(d));  // the initial simplex at once
    while (!e->Done()) ASSERT_TRUE(e->Tell(Evaluate(e->Ask(), bench::Rosenbrock)).ok());
    const auto best = e->HallOfFame()[0];
    EXPECT_LT(-best.eval.fitness, 1e-8) << "d = " << d;
    for (double x : best.genes) EXPECT_NEAR(x, 1.0, 1e-4);
    EXPECT_LT(e->searches()[0].iterations(), 2000);  // ended by the tolerance
  }
}

TEST(SweepEngineTest, SearchesShareBatchesAndEachFindsItsOwnMinimum) {
  // Rastrigin in 2-D: the top 3 grid points lie in different basins.
  SweepConfig c = RosenbrockConfig(2, 9, 3);
  c.nm_tolerance = 1e-9;
  auto e = Make(c);
  ASSERT_TRUE(e->Tell(Evaluate(e->Ask(), bench::Rastrigin)).ok());
  EXPECT_EQ(e->Ask().size(), 6u);  // 3 initial simplices of 2 new points each
  size_t largest = 0;
  while (!e->Done()) {
    largest = std::max(largest, e->Ask().size());
    ASSERT_TRUE(e->Tell(Evaluate(e->Ask(), bench::Rastrigin)).ok());
  }
  EXPECT_LE(largest, 6u);
  for (const auto& s : e->searches()) EXPECT_TRUE(s.done());
  EXPECT_LT(-e->HallOfFame()[0].eval.fitness, 1e-8);  // (0, 0) is on the 9-point grid
}

TEST(SweepEngineTest, SaveLoadContinueIsBitIdentical) {
  SweepConfig c = RosenbrockConfig(3, 4, 2);
  c.grid_batch = 10;
  auto a = Make(c);
  for (int checkpoint : {0, 3, 8, 40, 90}) {
    while (a->generation() < checkpoint && !a->Done())
      ASSERT_TRUE(a->Tell(Evaluate(a->Ask(), bench::Rosenbrock)).ok());
    auto b = Make(c);
    ASSERT_TRUE(b->LoadState(a->SaveState()).ok());
    auto a2 = Make(c);
    ASSERT_TRUE(a2->LoadState(a->SaveState()).ok());
    for (int k = 0; k < 50 && !a2->Done(); ++k) {
      ASSERT_EQ(a2->Ask().size(), b->Ask().size());
      for (size_t m = 0; m < b->Ask().size(); ++m)
        ASSERT_EQ(a2->Ask()[m].genes, b->Ask()[m].genes);
      const auto evals = Evaluate(a2->Ask(), bench::Rosenbrock);
      ASSERT_TRUE(a2->Tell(evals).ok());
      ASSERT_TRUE(b->Tell(evals).ok());
    }
    EXPECT_EQ(a2->SaveState(), b->SaveState());
  }
  auto other = Make(RosenbrockConfig(3, 5, 2));
  EXPECT_EQ(other->LoadState(a->SaveState()).code(), absl::StatusCode::kFailedPrecondition);
  const std::string s = a->SaveState();
  EXPECT_EQ(a->LoadState(s.substr(0, s.size() - 3)).code(), absl::StatusCode::kDataLoss);
}

TEST(SweepEngineTest, TellChecksInputsAndBudgetEndsTheSweep) {
  SweepConfig c = RosenbrockConfig(2, 5, 2);
  c.max_evaluations = 40;
  auto e = Make(c);
  const std::string before = e->SaveState();
  auto evals = Evaluate(e->Ask(), bench::Rosenbrock);
  evals.pop_back();
  EXPECT_EQ(e->Tell(evals).code(), absl::StatusCode::kInvalidArgument);
  evals = Evaluate(e->Ask(), bench::Rosenbrock);
  evals[0].fitness = INFINITY;
  EXPECT_EQ(e->Tell(evals).code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(e->SaveState(), before);
  while (!e->Done()) ASSERT_TRUE(e->Tell(Evaluate(e->Ask(), bench::Rosenbrock)).ok());
  EXPECT_LE(e->evaluations(), 40);
  EXPECT_GT(e->evaluations(), 35);
}

// Minimise the sphere subject to x_0 >= 0.5: Nelder-Mead ranks by Deb's rule and ends on
// the constraint's face.
TEST(SweepEngineTest, InfeasiblePointsRankBelowFeasibleOnes) {
  SweepConfig c = RosenbrockConfig(2, 5, 1);
  auto e = Make(c);
  while (!e->Done()) {
    std::vector<Evaluation> evals;
    for (const auto& cand : e->Ask())
      evals.push_back({true, -bench::Sphere(cand.genes), "",
                       std::max(0.0, 0.5 - cand.genes[0])});
    ASSERT_TRUE(e->Tell(evals).ok());
  }
  const auto best = e->HallOfFame()[0];
  EXPECT_EQ(best.eval.violation, 0.0);
  EXPECT_NEAR(best.genes[0], 0.5, 1e-4);
  EXPECT_NEAR(best.genes[1], 0.0, 1e-4);
}

}  // namespace
}  // namespace gaitforge::engines::sweep
