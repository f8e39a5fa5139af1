#pragma once
// NSGA-II (Deb, Pratap, Agarwal, Meyarivan 2002) in ask/tell form, for studies with several
// objectives (the metrics `nsga2.objectives` names; docs/engines.md):
//  - generation 0: `population` members uniform in their ranges (streams (seed, 0, m, kInit));
//  - every later generation: `population` offspring of the parents, each pair from two
//    binary tournaments (lower front first, then larger crowding distance, then the first
//    drawn; stream (seed, g, first child, kSelect)), SBX at `crossover_rate` with index
//    `crossover_eta` (seed, g, first child, kCrossover), polynomial mutation of each gene at
//    `mutation_rate` with index `mutation_eta` (seed, g, child, kMutate);
//  - Tell: parents and offspring together are sorted into fronts by constrained domination
//    (pareto.h) and the next parents are the first fronts that fit, the last one cut by
//    crowding distance (larger first, then earlier index: parents before offspring).
// Every member of every generation is new (nothing carried). The hall of fame is the
// parents' first front, distinct genotypes, ordered by the first objective (best first).
#include <cstdint>
#include <memory>
#include <string>

#include "services/engines/engine.h"

namespace gaitforge::engines::nsga2 {

struct Nsga2Config {
  uint64_t seed = 0;
  int population = 100;
  int generations = 100;
  int objectives = 2;  // how many objectives each valid Evaluation carries
  double crossover_rate = 0.9, crossover_eta = 20, mutation_eta = 20;
  double mutation_rate = 0;  // 0: one over the number of genes
  Bounds bounds;
};

inline constexpr int kMaxPopulation = 10000;  // sorting costs population squared

// Checks a configuration; the message names the field and its allowed range.
absl::Status ValidateNsga2Config(const Nsga2Config& config);

class Nsga2Engine final : public Engine {
 public:
  Nsga2Engine(const Nsga2Engine&) = delete;
  Nsga2Engine& operator=(const Nsga2Engine&) = delete;

  static absl::StatusOr<std::unique_ptr<Nsga2Engine>> Create(const Nsga2Config& config);

  int generation() const override { return generation_; }
  bool Done() const override { return generation_ >= config_.generations; }
  const std::vector<Candidate>& Ask() const override { return candidates_; }
  absl::Status Tell(const std::vector<Evaluation>& by_member) override;
  std::vector<Ranked> HallOfFame() const override { return hof_; }
  std::string SaveState() const override;
  absl::Status LoadState(std::string_view state) override;

  // The parents after the last Tell, with their evaluations (for tests and reports).
  const std::vector<Ranked>& parents() const { return parents_; }

 private:
  explicit Nsga2Engine(const Nsga2Config& config);
  void InitialPopulation();
  absl::Status CheckTold(const std::vector<Evaluation>& evals) const;
  void SelectParents(std::vector<Ranked> pool);
  void Breed();

  Nsga2Config config_;
  int generation_ = 0;
  std::vector<Candidate> candidates_;
  std::vector<Ranked> parents_;
  std::vector<int> parent_front_;        // per parent: its front (0 best)
  std::vector<double> parent_crowding_;  // per parent: its crowding distance
  std::vector<Ranked> hof_;
};

}  // namespace gaitforge::engines::nsga2
