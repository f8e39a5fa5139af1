// Log-scaled genes: the wrapped engine searches ln(x), everything reported is in the gene's
// units and inside its bounds, the state round-trips, and the spread maps back.
#include <gtest/gtest.h>

#include <cmath>

#include "services/engines/cmaes/cmaes_engine.h"
#include "services/engines/ga/ga_engine.h"
#include "services/engines/log_genes.h"

namespace gaitforge::engines {
namespace {

Bounds Decades() {  // a creep's range: five decades
  Bounds b;
  b.lo = {1e-5};
  b.hi = {1.0};
  return b;
}

Bounds InLogSpace(const Bounds& natural) {
  Bounds b = natural;
  for (size_t i = 0; i < b.size(); ++i) {
    b.lo[i] = ToLogSpace(b.lo[i]);
    b.hi[i] = ToLogSpace(b.hi[i]);
  }
  return b;
}

std::unique_ptr<Engine> Ga(const Bounds& bounds) {
  ga::GaConfig c;
  c.seed = 5;
  c.population = 400;
  c.bounds = bounds;
  auto e = ga::GaEngine::Create(c);
  EXPECT_TRUE(e.ok()) << e.status();
  return std::move(*e);
}

std::unique_ptr<Engine> Cmaes(const Bounds& bounds, double mean0) {
  cmaes::CmaesConfig c;
  c.seed = 7;
  c.bounds = bounds;
  c.mean0 = {mean0};
  c.sigma0_fraction = 0.25;
  c.population = 8;
  auto e = cmaes::CmaesEngine::Create(c);
  EXPECT_TRUE(e.ok()) << e.status();
  return std::move(*e);
}

double ShareBelow(const std::vector<Candidate>& members, double x) {
  int n = 0;
  for (const auto& m : members) n += m.genes[0] < x;
  return static_cast<double>(n) / members.size();
}

// The GA's uniform first draw: linear puts 1% below 0.01, log-uniform three fifths.
TEST(LogGenes, TheFirstDrawCoversEveryDecadeAlike) {
  const Bounds natural = Decades();
  EXPECT_LT(ShareBelow(Ga(natural)->Ask(), 0.01), 0.05);
  LogGenesEngine log(Ga(InLogSpace(natural)), {true}, natural);
  EXPECT_NEAR(ShareBelow(log.Ask(), 0.01), 0.6, 0.1);
  EXPECT_GT(ShareBelow(log.Ask(), 1e-4), 0.1);
  for (const auto& m : log.Ask()) {
    EXPECT_GE(m.genes[0], natural.lo[0]);
    EXPECT_LE(m.genes[0], natural.hi[0]);
  }
}

// CMA-ES on -(log10 x + 3.5)^2 reaches x = 10^-3.5 to within 1% and reports it in units.
TEST(LogGenes, CmaesFindsAValueDecadesBelowTheRangesMiddle) {
  const Bounds natural = Decades();
  LogGenesEngine e(Cmaes(InLogSpace(natural), ToLogSpace(0.1)), {true}, natural);
  for (int g = 0; g < 60 && !e.Done(); ++g) {
    std::vector<Evaluation> evals;
    for (const auto& m : e.Ask())
      evals.push_back({true, -std::pow(std::log10(m.genes[0]) + 3.5, 2), "", 0});
    ASSERT_TRUE(e.Tell(evals).ok());
  }
  const double best = e.HallOfFame().at(0).genes[0];
  EXPECT_NEAR(best, std::pow(10.0, -3.5), 0.01 * std::pow(10.0, -3.5));
  // The spread is the log-space deviation s mapped as best * sinh(s): small against best.
  ASSERT_EQ(e.Spread().size(), 1u);
  EXPECT_GT(e.Spread()[0], 0.0);
  EXPECT_LT(e.Spread()[0], 0.1 * best);
}

// The wrapper's state is the inner engine's: a fresh wrapper loaded with it asks the same.
TEST(LogGenes, StateRoundTripsBitExactly) {
  const Bounds natural = Decades();
  LogGenesEngine a(Cmaes(InLogSpace(natural), ToLogSpace(1e-3)), {true}, natural);
  std::vector<Evaluation> evals;
  for (const auto& m : a.Ask()) evals.push_back({true, -m.genes[0], "", 0});
  ASSERT_TRUE(a.Tell(evals).ok());
  LogGenesEngine b(Cmaes(InLogSpace(natural), ToLogSpace(1e-3)), {true}, natural);
  ASSERT_TRUE(b.LoadState(a.SaveState()).ok());
  ASSERT_EQ(a.Ask().size(), b.Ask().size());
  for (size_t i = 0; i < a.Ask().size(); ++i) EXPECT_EQ(a.Ask()[i].genes, b.Ask()[i].genes);
  EXPECT_EQ(b.generation(), 1);
}

// Samples from the lower edge with the whole range as step: exp(ln(lo)) may round below
// lo, and the reported gene never leaves the spec's range; a linear gene beside it is as is.
TEST(LogGenes, EdgesStayInsideTheRange) {
  Bounds natural;
  natural.lo = {1e-5, 0.3};
  natural.hi = {1.0, 5.0};
  Bounds inner = InLogSpace(natural);
  inner.lo[1] = natural.lo[1];  // the second gene stays linear
  inner.hi[1] = natural.hi[1];
  cmaes::CmaesConfig c;
  c.seed = 11;
  c.bounds = inner;
  c.mean0 = {inner.lo[0], inner.hi[1]};
  c.sigma0_fraction = 1.0;
  c.population = 200;
  auto made = cmaes::CmaesEngine::Create(c);
  ASSERT_TRUE(made.ok());
  LogGenesEngine e(std::move(*made), {true, false}, natural);
  for (const auto& m : e.Ask()) {
    EXPECT_GE(m.genes[0], 1e-5);
    EXPECT_LE(m.genes[0], 1.0);
    EXPECT_GE(m.genes[1], 0.3);
    EXPECT_LE(m.genes[1], 5.0);
  }
}

}  // namespace
}  // namespace gaitforge::engines
