#include "services/engines/ga/ga_operators.h"

#include <gtest/gtest.h>

#include <cmath>

namespace gaitforge::engines::ga {
namespace {

using core::KeyedRng;
using core::Purpose;

TEST(RouletteWeights, ShiftByWorstValidAndZeroForInvalid) {
  std::vector<Evaluation> e = {{true, -2.0, ""}, {true, 1.0, ""}, {false, 0, "x"}, {true, 3.0, ""}};
  const auto w = RouletteWeights(e);
  EXPECT_DOUBLE_EQ(w[0], 0.0);
  EXPECT_DOUBLE_EQ(w[1], 3.0);
  EXPECT_DOUBLE_EQ(w[2], 0.0);
  EXPECT_DOUBLE_EQ(w[3], 5.0);
}

TEST(RouletteWeights, AllEqualFallsBackToUniformOverValid) {
  std::vector<Evaluation> e = {{true, 1.0, ""}, {false, 0, "x"}, {true, 1.0, ""}};
  EXPECT_EQ(RouletteWeights(e), (std::vector<double>{1, 0, 1}));
  std::vector<Evaluation> all_bad = {{false, 0, "x"}, {false, 0, "y"}};
  EXPECT_EQ(RouletteWeights(all_bad), (std::vector<double>{1, 1}));
}

TEST(RouletteWeights, InfeasibleMembersAreNeverParentsAndRankBelowFeasible) {
  std::vector<Evaluation> e = {{true, 5.0, "", 0.3}, {true, 1.0, "", 0.0}, {true, 2.0, "", 0.0},
                               {true, 9.0, "", 0.1}};
  const auto w = RouletteWeights(e);
  EXPECT_EQ(w, (std::vector<double>{0, 0, 1, 0}));
  // Deb's rule: feasible by fitness, then infeasible by violation, whatever their fitness.
  EXPECT_TRUE(RanksBefore(e[2], 2, e[1], 1));
  EXPECT_TRUE(RanksBefore(e[1], 1, e[3], 3));
  EXPECT_TRUE(RanksBefore(e[3], 3, e[0], 0));
  EXPECT_TRUE(RanksBefore(e[0], 0, Evaluation{false, 0, "diverged"}, 4));
}

TEST(RouletteSelect, ProportionalToWeight) {
  const std::vector<double> w = {1, 0, 2, 3, 4};
  std::vector<int> counts(w.size(), 0);
  const int n = 200000;
  KeyedRng rng(3, 0, 0, Purpose::kSelect);
  for (int i = 0; i < n; ++i) ++counts[RouletteSelect(w, rng)];
  EXPECT_EQ(counts[1], 0);  // weight 0 never chosen
  for (size_t i = 0; i < w.size(); ++i) {
    const double p = w[i] / 10.0;
    const double sd = std::sqrt(n * p * (1 - p));
    EXPECT_NEAR(counts[i], n * p, 4 * sd + 1) << "member " << i;
  }
}

TEST(RouletteSelect, CumulativeFormPicksTheSameIndexForTheSameStream) {
  const std::vector<double> w = {0, 1.5, 0, 0, 2.5, 0.25, 0};
  const auto c = Cumulative(w);
  for (uint64_t k = 0; k < 5000; ++k) {
    KeyedRng a(k, 1, 2, Purpose::kSelect), b(k, 1, 2, Purpose::kSelect);
    const int i = RouletteSelect(w, a);
    EXPECT_EQ(i, RouletteSelectCumulative(c, b));
    EXPECT_GT(w[i], 0.0);
  }
}

TEST(SwapPrefix, SwapsExactlyTheFirstNGenes) {
  std::vector<double> a = {1, 2, 3, 4, 5}, b = {6, 7, 8, 9, 10};
  SwapPrefix(a, b, 2);
  EXPECT_EQ(a, (std::vector<double>{6, 7, 3, 4, 5}));
  EXPECT_EQ(b, (std::vector<double>{1, 2, 8, 9, 10}));
}

TEST(MutateReinit, RateIsAboutTenPercentAndValuesStayInBounds) {
  Bounds bounds;
  for (int i = 0; i < 12; ++i) {
    bounds.lo.push_back(0);
    bounds.hi.push_back(1);
  }
  bounds.lo.push_back(0.2);
  bounds.hi.push_back(2.0);
  int changed = 0, total = 0;
  for (int child = 0; child < 20000; ++child) {
    std::vector<double> g(13, -1.0);  // outside the bounds: any change is visible
    KeyedRng rng(9, 1, child, Purpose::kMutate);
    changed += MutateReinit(g, bounds, 0.10, rng);
    total += 13;
    for (size_t i = 0; i < g.size(); ++i) {
      if (g[i] == -1.0) continue;
      ASSERT_GE(g[i], bounds.lo[i]);
      ASSERT_LT(g[i], bounds.hi[i]);
    }
  }
  const double rate = static_cast<double>(changed) / total;
  const double sd = std::sqrt(0.1 * 0.9 / total);  // ~0.00058
  EXPECT_NEAR(rate, 0.10, 4 * sd);
}

}  // namespace
}  // namespace gaitforge::engines::ga
