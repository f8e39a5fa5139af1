// The Engine contract for CMA-ES: keyed determinism, bit-identical save/load/continue,
// candidates inside the box, Deb's rule for infeasible members, input checks, budget,
// hall of fame.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "bench/cmaes_functions.h"
#include "services/engines/cmaes/cmaes_engine.h"

namespace gaitforge::engines::cmaes {
namespace {

CmaesConfig SmallConfig(uint64_t seed, int d, Restarts restarts = Restarts::kNone) {
  CmaesConfig c;
  c.seed = seed;
  c.bounds.lo.assign(d, -5.12);
  c.bounds.hi.assign(d, 5.12);
  c.sigma0_fraction = 0.3;
  c.restarts = restarts;
  c.max_evaluations = 200000;
  return c;
}

std::unique_ptr<CmaesEngine> Make(const CmaesConfig& c) {
  auto e = CmaesEngine::Create(c);
  EXPECT_TRUE(e.ok()) << e.status();
  return std::move(*e);
}

std::vector<Evaluation> Evaluate(const std::vector<Candidate>& cands) {
  std::vector<Evaluation> evals;
  for (const auto& c : cands) evals.push_back({true, -bench::Rastrigin(c.genes), ""});
  return evals;
}

bool SameBits(const std::vector<Candidate>& a, const std::vector<Candidate>& b) {
  if (a.size() != b.size()) return false;
  for (size_t m = 0; m < a.size(); ++m) {
    if (a[m].genes.size() != b[m].genes.size() ||
        std::memcmp(a[m].genes.data(), b[m].genes.data(), a[m].genes.size() * sizeof(double)))
      return false;
  }
  return true;
}

TEST(CmaesContractTest, SameSeedSameAskSequence) {
  auto a = Make(SmallConfig(7, 5, Restarts::kBipop));
  auto b = Make(SmallConfig(7, 5, Restarts::kBipop));
  auto other = Make(SmallConfig(8, 5, Restarts::kBipop));
  EXPECT_FALSE(SameBits(a->Ask(), other->Ask()));
  for (int g = 0; g < 400 && !a->Done(); ++g) {
    ASSERT_TRUE(SameBits(a->Ask(), b->Ask())) << "generation " << g;
    const auto evals = Evaluate(a->Ask());
    ASSERT_TRUE(a->Tell(evals).ok());
    ASSERT_TRUE(b->Tell(evals).ok());
  }
  EXPECT_EQ(a->SaveState(), b->SaveState());
  EXPECT_GT(a->runs(), 1);  // the sequence went through restarts
}

TEST(CmaesContractTest, SaveLoadContinueIsBitIdentical) {
  // Small tolerances make runs end and BIPOP restart within a few hundred generations.
  CmaesConfig c = SmallConfig(11, 4, Restarts::kBipop);
  c.tolfun = 1e-4;
  auto a = Make(c);
  int g = 0;
  for (int checkpoint : {0, 3, 57, 180, 333}) {
    for (; g < checkpoint && !a->Done(); ++g) ASSERT_TRUE(a->Tell(Evaluate(a->Ask())).ok());
    auto b = Make(c);
    ASSERT_TRUE(b->LoadState(a->SaveState()).ok());
    ASSERT_TRUE(SameBits(a->Ask(), b->Ask()));
    auto a2 = Make(c);
    ASSERT_TRUE(a2->LoadState(a->SaveState()).ok());
    for (int k = 0; k < 120 && !a2->Done(); ++k) {
      const auto evals = Evaluate(a2->Ask());
      ASSERT_TRUE(a2->Tell(evals).ok());
      ASSERT_TRUE(b->Tell(evals).ok());
      ASSERT_TRUE(SameBits(a2->Ask(), b->Ask())) << "checkpoint " << checkpoint << " +" << k;
    }
    EXPECT_EQ(a2->SaveState(), b->SaveState());
  }
  EXPECT_GT(a->runs(), 1);
}

TEST(CmaesContractTest, LoadRejectsForeignOrDamagedState) {
  auto a = Make(SmallConfig(1, 3));
  const std::string s = a->SaveState();
  auto other = Make(SmallConfig(2, 3));
  EXPECT_EQ(other->LoadState(s).code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_EQ(a->LoadState(s.substr(0, s.size() / 2)).code(), absl::StatusCode::kDataLoss);
  EXPECT_EQ(a->LoadState("nonsense").code(), absl::StatusCode::kDataLoss);
  EXPECT_EQ(a->SaveState(), s);  // failed loads change nothing
}

// f = sum (x_i - 3)^2 on [-1, 1]^d: the optimum is the corner (1, ..., 1). Every candidate
// lies in the box, and the search converges onto the corner instead of stalling.
TEST(CmaesContractTest, CandidatesInBoundsAndOptimumOnTheBoundaryIsReached) {
  CmaesConfig c;
  c.seed = 5;
  c.bounds.lo.assign(6, -1.0);
  c.bounds.hi.assign(6, 1.0);
  c.sigma0_fraction = 1.0;  // wide samples: many fall outside before the repair
  c.max_evaluations = 6000;
  auto e = Make(c);
  auto f = [](const std::vector<double>& x) {
    double s = 0;
    for (double v : x) s += (v - 3) * (v - 3);
    return s;
  };
  while (!e->Done()) {
    std::vector<Evaluation> evals;
    for (const auto& cand : e->Ask()) {
      for (size_t i = 0; i < cand.genes.size(); ++i) {
        ASSERT_GE(cand.genes[i], c.bounds.lo[i]);
        ASSERT_LE(cand.genes[i], c.bounds.hi[i]);
      }
      evals.push_back({true, -f(cand.genes), ""});
    }
    ASSERT_TRUE(e->Tell(evals).ok());
  }
  const auto hof = e->HallOfFame();
  ASSERT_FALSE(hof.empty());
  for (double v : hof[0].genes) EXPECT_NEAR(v, 1.0, 1e-6);
}

// Minimise the sphere subject to x_0 >= 2 (violation = max(0, 2 - x_0)); some members are
// also invalid. Infeasible members rank below feasible ones; the optimum is (2, 0, ...).
TEST(CmaesContractTest, ConstraintsByFeasibilityRule) {
  CmaesConfig c = SmallConfig(3, 5);
  c.max_evaluations = 20000;
  auto e = Make(c);
  while (!e->Done()) {
    std::vector<Evaluation> evals;
    for (const auto& cand : e->Ask()) {
      const double viol = std::max(0.0, 2.0 - cand.genes[0]);
      Evaluation ev{true, -bench::Sphere(cand.genes), "", viol};
      if (cand.member == 1) ev = {false, 0.0, "simulation diverged"};
      evals.push_back(ev);
    }
    ASSERT_TRUE(e->Tell(evals).ok());
  }
  const auto hof = e->HallOfFame();
  ASSERT_EQ(hof.size(), 10u);
  EXPECT_EQ(hof[0].eval.violation, 0.0);
  EXPECT_NEAR(hof[0].genes[0], 2.0, 1e-4);
  EXPECT_NEAR(-hof[0].eval.fitness, 4.0, 1e-3);
  for (size_t i = 1; i < hof.size(); ++i)
    EXPECT_FALSE(RanksBefore(hof[i].eval, 0, hof[i - 1].eval, 0));  // best first
}

TEST(CmaesContractTest, TellChecksInputsBeforeChangingState) {
  auto e = Make(SmallConfig(1, 3));
  const std::string before = e->SaveState();
  auto evals = Evaluate(e->Ask());
  evals.pop_back();
  EXPECT_EQ(e->Tell(evals).code(), absl::StatusCode::kInvalidArgument);
  evals = Evaluate(e->Ask());
  evals[2].fitness = NAN;
  EXPECT_EQ(e->Tell(evals).code(), absl::StatusCode::kInvalidArgument);
  evals[2].fitness = 0;
  evals[3].violation = -1;
  EXPECT_EQ(e->Tell(evals).code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(e->SaveState(), before);
  EXPECT_EQ(e->generation(), 0);
}

TEST(CmaesContractTest, BudgetEndsTheRunAndIsNeverExceeded) {
  CmaesConfig c = SmallConfig(1, 3, Restarts::kIpop);
  c.max_evaluations = 95;  // lambda = 7
  auto e = Make(c);
  while (!e->Done()) ASSERT_TRUE(e->Tell(Evaluate(e->Ask())).ok());
  EXPECT_EQ(e->evaluations(), 91);
  EXPECT_EQ(e->stop_reason(), "max_evaluations");
  EXPECT_EQ(e->Tell({}).code(), absl::StatusCode::kFailedPrecondition);
}

TEST(CmaesContractTest, HallOfFameRecordsWhereEachWasEvaluated) {
  auto e = Make(SmallConfig(4, 3));
  std::map<std::pair<int, int>, std::vector<double>> seen;
  for (int g = 0; g < 60 && !e->Done(); ++g) {
    for (const auto& c : e->Ask()) {
      EXPECT_EQ(c.origin_generation, e->generation());
      seen[{c.origin_generation, c.member}] = c.genes;
    }
    ASSERT_TRUE(e->Tell(Evaluate(e->Ask())).ok());
  }
  const auto hof = e->HallOfFame();
  ASSERT_EQ(hof.size(), 10u);
  for (const auto& h : hof) {
    EXPECT_EQ(seen.at({h.generation, h.member}), h.genes);
    EXPECT_DOUBLE_EQ(h.eval.fitness, -bench::Rastrigin(h.genes));
  }
}

}  // namespace
}  // namespace gaitforge::engines::cmaes
