#pragma once
// Paper 000's GA, exactly (../shared/papers/, paper 000, section on the GA), for any gene space:
//  - generation 0: every gene uniform in its range;
//  - the `elite` best (the hall of fame, 10 in the paper) pass unchanged to the next
//    generation, with their evaluation (they are not evaluated again);
//  - the rest come in pairs: two parents by roulette wheel (ga_operators.h for the
//    weights), one-point crossover swapping the first N genes, N drawn once per generation
//    in [1, genes - 1]; each gene of each child re-initialised with probability
//    `mutation_rate` (0.10 in the paper). An odd remainder drops the second child.
// Random streams: (seed, g, 0, kCrossover) for N; (seed, g, first child, kSelect) for a
// pair's parents; (seed, g, child, kMutate) for a child's mutation; (seed, 0, m, kInit)
// for the initial population. g is the generation being created.
//
// Paper 004's real-coded GA (its arm's fact sheet) swaps operators, each on its own:
// selection "tournament" (3 members, ga_operators.h), crossover "blend" (BLX-0.5 at rate
// 0.8, one decision per pair from (seed, g, first child, kCrossover)), mutation "gaussian"
// (a normal step of 0.1 of the range at `mutation_rate` per gene).
#include <cstdint>
#include <optional>
#include <string>

#include "services/engines/engine.h"

namespace gaitforge::engines::ga {

struct GaConfig {
  uint64_t seed = 0;
  int population = 200;
  int generations = 150;
  int elite = 10;
  double mutation_rate = 0.10;
  Bounds bounds;
  // Stop after a generation whose best member is feasible with fitness >= this (optional).
  // Read from the hall of fame, so a resumed study stops where the first run would have.
  std::optional<double> stop_fitness;
  std::string selection = "roulette";   // or "tournament"
  std::string crossover = "one_point";  // or "blend"
  std::string mutation = "reinit";      // or "gaussian"
};

inline constexpr int kTournamentSize = 3;
inline constexpr double kBlendRate = 0.8, kBlendAlpha = 0.5, kGaussianSdFraction = 0.1;

// Checks a configuration; the message names the field and its allowed range.
absl::Status ValidateGaConfig(const GaConfig& config);

class GaEngine final : public Engine {
 public:
  // Not copyable or movable: owned through unique_ptr.
  GaEngine(const GaEngine&) = delete;
  GaEngine& operator=(const GaEngine&) = delete;

  static absl::StatusOr<std::unique_ptr<GaEngine>> Create(const GaConfig& config);

  int generation() const override { return generation_; }
  bool Done() const override { return generation_ >= config_.generations || ReachedStopFitness(hof_); }
  std::string StopReason() const override;
  const std::vector<Candidate>& Ask() const override { return candidates_; }
  absl::Status Tell(const std::vector<Evaluation>& by_member) override;
  std::vector<Ranked> HallOfFame() const override { return hof_; }
  std::string SaveState() const override;
  absl::Status LoadState(std::string_view state) override;

  // The crossover point used to create generation g (>= 1). Exposed for tests.
  int CrossoverPoint(int g) const;

 private:
  explicit GaEngine(const GaConfig& config);
  void InitialPopulation();
  bool ReachedStopFitness(const std::vector<Ranked>& hof) const;
  void Breed(const std::vector<Evaluation>& evals, const std::vector<int>& order);

  GaConfig config_;
  int generation_ = 0;
  std::vector<Candidate> candidates_;
  std::vector<Candidate> spare_;  // the other population buffer (not state)
  std::vector<Ranked> hof_;
};

}  // namespace gaitforge::engines::ga
