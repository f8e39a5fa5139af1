// Circular (phase) genes: CMA-ES wraps them across the seam instead of reflecting, the
// sweep's grid does not count the seam twice, Nelder-Mead steps across it, and halls of
// fame hold distinct gaits (a copy, or every phase shifted by one amount, is the same).
#include <gtest/gtest.h>

#include <cmath>

#include "services/engines/cmaes/cmaes_engine.h"
#include "services/engines/ga/ga_engine.h"
#include "services/engines/hall_of_fame.h"
#include "services/engines/sweep/sweep_engine.h"

namespace gaitforge::engines {
using cmaes::CmaesConfig;
using cmaes::CmaesEngine;
using ga::GaConfig;
using ga::GaEngine;
using sweep::SweepConfig;
using sweep::SweepEngine;
namespace {

Bounds Phases(int n, bool circular) {
  Bounds b;
  b.lo.assign(n, 0.0);
  b.hi.assign(n, 1.0);
  b.circular.assign(n, circular);
  return b;
}

Evaluation Fit(double f) { return Evaluation{true, f, "", 0}; }

TEST(Circular, FoldWrapsACircularGeneAndClampsAnother) {
  Bounds b = Phases(2, false);
  b.circular[0] = true;
  EXPECT_NEAR(b.Fold(0, 1.02), 0.02, 1e-12);
  EXPECT_NEAR(b.Fold(0, -0.03), 0.97, 1e-12);
  EXPECT_EQ(b.Fold(0, 1.0), 0.0);
  EXPECT_EQ(b.Fold(1, 1.02), 1.0);
  EXPECT_NEAR(b.Near(0, 0.01, 0.99), 1.01, 1e-12);
}

// CMA-ES sampling near 0.99 with a small step: a circular gene crosses 0 to near 0.01; a
// bounded one reflects and stays below 1.
TEST(Circular, CmaesSamplesACircularGeneAcrossTheSeam) {
  for (const bool circular : {true, false}) {
    CmaesConfig c;
    c.seed = 3;
    c.bounds = Phases(2, circular);
    c.mean0 = {0.99, 0.99};
    c.sigma0_fraction = 0.02;
    c.population = 40;
    auto e = CmaesEngine::Create(c);
    ASSERT_TRUE(e.ok()) << e.status();
    int across = 0;
    for (const Candidate& k : (*e)->Ask()) {
      for (double g : k.genes) {
        EXPECT_GE(g, 0.0);
        EXPECT_LE(g, 1.0);
        if (g < 0.1) ++across;
        if (circular) {
          EXPECT_LT(g, 1.0);
        }
      }
    }
    if (circular) EXPECT_GT(across, 5);
    else EXPECT_EQ(across, 0);
  }
}

TEST(Circular, TheSameGaitUpToOneShiftOfEveryPhaseIsOneGenotype) {
  Bounds b = Phases(3, true);
  b.lo.push_back(0.2);  // a period gene, not circular
  b.hi.push_back(2.0);
  b.circular.push_back(false);
  const std::vector<double> a = {0.1, 0.5, 0.95, 0.8};
  EXPECT_TRUE(SameGenotype(a, {0.35, 0.75, 0.2, 0.8}, b));   // +0.25, wrapped
  EXPECT_FALSE(SameGenotype(a, {0.35, 0.75, 0.25, 0.8}, b));  // one phase moved more
  EXPECT_FALSE(SameGenotype(a, {0.35, 0.75, 0.2, 0.9}, b));   // another period
  EXPECT_FALSE(SameGenotype(a, {0.35, 0.75, 0.2, 0.8}, Phases(4, false)));
}

TEST(Circular, AHallOfFameKeepsTheBetterOfTwoShiftedCopies) {
  HallOfFame hof(3, Phases(2, true));
  hof.Offer(0, 0, {0.1, 0.4}, Fit(1.0));
  hof.Offer(0, 1, {0.6, 0.9}, Fit(0.5));  // the same gait half a cycle later: worse, left out
  hof.Offer(0, 2, {0.2, 0.4}, Fit(0.7));
  hof.Offer(1, 0, {0.3, 0.6}, Fit(2.0));  // the first one shifted, better: replaces it
  ASSERT_EQ(hof.entries().size(), 2u);
  EXPECT_EQ(hof.entries()[0].genes, (std::vector<double>{0.3, 0.6}));
  EXPECT_EQ(hof.entries()[1].genes, (std::vector<double>{0.2, 0.4}));
}

// The paper's GA breeds copies (crossover of equal parents, elites carried); its hall of
// fame reports distinct gaits only.
TEST(Circular, TheGasHallOfFameHoldsNoTwoEqualGaits) {
  GaConfig c;
  c.seed = 1;
  c.population = 10;
  c.generations = 15;
  c.elite = 5;
  c.mutation_rate = 0.05;
  c.bounds = Phases(2, true);
  auto e = GaEngine::Create(c);
  ASSERT_TRUE(e.ok()) << e.status();
  int copies_bred = 0;
  while (!(*e)->Done()) {
    const auto& cand = (*e)->Ask();
    std::vector<Evaluation> evals;
    for (size_t m = 0; m < cand.size(); ++m) {
      // Depends on the phase difference only: a shifted gait is as good.
      evals.push_back(Fit(std::cos(2 * M_PI * (cand[m].genes[0] - cand[m].genes[1]))));
      for (size_t k = 0; k < m; ++k) copies_bred += SameGenotype(cand[m].genes, cand[k].genes, c.bounds);
    }
    ASSERT_TRUE((*e)->Tell(evals).ok());
    const auto hof = (*e)->HallOfFame();
    for (size_t i = 0; i < hof.size(); ++i)
      for (size_t j = i + 1; j < hof.size(); ++j)
        EXPECT_FALSE(SameGenotype(hof[i].genes, hof[j].genes, c.bounds));
  }
  EXPECT_GT(copies_bred, 0);  // the test means something
}

TEST(Circular, TheSweepGridDoesNotCountTheSeamTwice) {
  SweepConfig c;
  c.bounds = Phases(1, true);
  c.points_per_axis = {4};
  c.top_k = 1;
  auto e = SweepEngine::Create(c);
  ASSERT_TRUE(e.ok()) << e.status();
  std::vector<double> xs;
  for (const Candidate& k : (*e)->Ask()) xs.push_back(k.genes[0]);
  EXPECT_EQ(xs, (std::vector<double>{0, 0.25, 0.5, 0.75}));
}

}  // namespace
}  // namespace gaitforge::engines
