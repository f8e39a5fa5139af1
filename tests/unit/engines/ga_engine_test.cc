#include "services/engines/ga/ga_engine.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>

namespace gaitforge::engines::ga {
namespace {

GaConfig Config(uint64_t seed = 42, int pop = 60, int gens = 8, double rate = 0.10) {
  GaConfig c;
  c.seed = seed;
  c.population = pop;
  c.generations = gens;
  c.elite = 10;
  c.mutation_rate = rate;
  for (int i = 0; i < 12; ++i) {
    c.bounds.lo.push_back(0);
    c.bounds.hi.push_back(1);
  }
  c.bounds.lo.push_back(0.2);
  c.bounds.hi.push_back(2.0);
  return c;
}

// A deterministic test fitness: higher near genes = 0.3.
std::vector<Evaluation> Score(const std::vector<Candidate>& cands) {
  std::vector<Evaluation> out;
  for (const auto& c : cands) {
    double f = 0;
    for (double x : c.genes) f -= (x - 0.3) * (x - 0.3);
    out.push_back({true, f, ""});
  }
  return out;
}

std::unique_ptr<GaEngine> Make(const GaConfig& c) {
  auto e = GaEngine::Create(c);
  EXPECT_TRUE(e.ok()) << e.status();
  return std::move(*e);
}

TEST(GaEngine, HallOfFameIsCarriedUnchangedWithItsEvaluation) {
  auto ga = Make(Config());
  for (int g = 0; g < 5; ++g) {
    const auto cands = ga->Ask();
    const auto evals = Score(cands);
    std::vector<int> order(cands.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return RanksBefore(evals[a], a, evals[b], b); });
    ASSERT_TRUE(ga->Tell(evals).ok());
    const auto& next = ga->Ask();
    const auto hof = ga->HallOfFame();
    // The hall of fame: the best distinct genotypes (copies bred this generation left out).
    std::vector<int> distinct;
    for (int i : order) {
      bool copy = false;
      for (int d : distinct) copy = copy || SameGenotype(cands[i].genes, cands[d].genes, Config().bounds);
      if (!copy && distinct.size() < 10) distinct.push_back(i);
    }
    ASSERT_EQ(hof.size(), 10u);
    for (int r = 0; r < 10; ++r) {
      EXPECT_EQ(next[r].member, r);
      EXPECT_EQ(next[r].genes, cands[order[r]].genes) << "rank " << r;
      ASSERT_TRUE(next[r].known.has_value());
      EXPECT_EQ(next[r].known->fitness, evals[order[r]].fitness);
      EXPECT_EQ(hof[r].genes, cands[distinct[r]].genes);
      EXPECT_EQ(hof[r].eval.fitness, evals[distinct[r]].fitness);
    }
    for (size_t m = 10; m < next.size(); ++m) EXPECT_FALSE(next[m].known.has_value());
  }
}

TEST(GaEngine, CrossoverSwapsTheFirstNGenesWithOneNPerGeneration) {
  // Without mutation every child pair must be (q[:N] + p[N:], p[:N] + q[N:]) for parents
  // p, q of the previous generation and the generation's single N.
  auto ga = Make(Config(7, 40, 6, 0.0));
  std::set<int> points;
  for (int g = 0; g < 5; ++g) {
    const auto parents = ga->Ask();
    ASSERT_TRUE(ga->Tell(Score(parents)).ok());
    const int n = ga->CrossoverPoint(g + 1);
    ASSERT_GE(n, 1);
    ASSERT_LE(n, 12);
    points.insert(n);
    const auto& kids = ga->Ask();
    for (size_t first = 10; first + 1 < kids.size(); first += 2) {
      const auto& a = kids[first].genes;
      const auto& b = kids[first + 1].genes;
      bool found = false;
      for (const auto& p : parents) {
        for (const auto& q : parents) {
          bool ok = true;
          for (int i = 0; i < 13 && ok; ++i) {
            ok = a[i] == (i < n ? q.genes[i] : p.genes[i]) &&
                 b[i] == (i < n ? p.genes[i] : q.genes[i]);
          }
          found = found || ok;
        }
      }
      EXPECT_TRUE(found) << "generation " << g + 1 << " pair at " << first << " with N = " << n;
    }
  }
  EXPECT_GT(points.size(), 1u) << "N is drawn anew each generation";
}

TEST(GaEngine, SameSeedSameStudyDifferentSeedDifferentStudy) {
  auto run = [](uint64_t seed) {
    auto ga = Make(Config(seed));
    std::vector<std::vector<double>> all;
    while (!ga->Done()) {
      for (const auto& c : ga->Ask()) all.push_back(c.genes);
      EXPECT_TRUE(ga->Tell(Score(ga->Ask())).ok());
    }
    return all;
  };
  EXPECT_EQ(run(5), run(5));
  EXPECT_NE(run(5), run(6));
}

TEST(GaEngine, SaveLoadContinuesBitIdentically) {
  auto a = Make(Config(11));
  for (int g = 0; g < 3; ++g) ASSERT_TRUE(a->Tell(Score(a->Ask())).ok());
  auto b = Make(Config(11));
  ASSERT_TRUE(b->LoadState(a->SaveState()).ok());
  EXPECT_EQ(b->generation(), 3);
  while (!a->Done()) {
    ASSERT_EQ(a->Ask().size(), b->Ask().size());
    for (size_t m = 0; m < a->Ask().size(); ++m) EXPECT_EQ(a->Ask()[m].genes, b->Ask()[m].genes);
    ASSERT_TRUE(a->Tell(Score(a->Ask())).ok());
    ASSERT_TRUE(b->Tell(Score(b->Ask())).ok());
  }
  EXPECT_TRUE(b->Done());
  EXPECT_EQ(a->SaveState(), b->SaveState());
}

TEST(GaEngine, LoadRejectsStateOfAnotherConfiguration) {
  auto a = Make(Config(11));
  auto b = Make(Config(12));
  EXPECT_EQ(b->LoadState(a->SaveState()).code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_EQ(b->LoadState("garbage").code(), absl::StatusCode::kDataLoss);
}

TEST(GaEngine, TellChecksInputsBeforeChangingState) {
  auto ga = Make(Config());
  const std::string before = ga->SaveState();
  auto evals = Score(ga->Ask());
  evals.pop_back();
  EXPECT_EQ(ga->Tell(evals).code(), absl::StatusCode::kInvalidArgument);
  evals = Score(ga->Ask());
  evals[3].fitness = NAN;
  EXPECT_EQ(ga->Tell(evals).code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(ga->SaveState(), before);
}

TEST(GaEngine, InvalidMembersRankLastAndAreNeverParents) {
  auto ga = Make(Config(3, 40, 3, 0.0));
  auto evals = Score(ga->Ask());
  for (size_t m = 0; m < evals.size(); m += 2) evals[m] = {false, 0, "diverged"};
  const auto parents = ga->Ask();
  ASSERT_TRUE(ga->Tell(evals).ok());
  for (const auto& h : ga->HallOfFame()) EXPECT_TRUE(h.eval.valid);
  // With mutation off, every gene of a child comes from a valid parent's same position.
  for (size_t k = 10; k < ga->Ask().size(); ++k) {
    for (int i = 0; i < 13; ++i) {
      bool from_valid = false;
      for (size_t m = 1; m < parents.size(); m += 2)
        from_valid = from_valid || parents[m].genes[i] == ga->Ask()[k].genes[i];
      EXPECT_TRUE(from_valid);
    }
  }
}

TEST(GaConfig, RejectsOutOfRangeValuesByName) {
  auto c = Config();
  c.population = 1;
  EXPECT_NE(ValidateGaConfig(c).message().find("population"), std::string::npos);
  c = Config();
  c.mutation_rate = 1.5;
  EXPECT_NE(ValidateGaConfig(c).message().find("mutation_rate"), std::string::npos);
  c = Config();
  c.bounds.hi[0] = c.bounds.lo[0];
  EXPECT_NE(ValidateGaConfig(c).message().find("bounds[0]"), std::string::npos);
}

}  // namespace
}  // namespace gaitforge::engines::ga
