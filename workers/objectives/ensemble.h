#pragma once
// Robust evaluation (docs/objectives.md, "Robust evaluation"): one genotype evaluated over
// an ensemble of numerically irrelevant variants, parameter samples and start phases, its
// fitness a statistic of the members' fitnesses. Every genotype of a study meets the same
// ensemble (drawn from the ensemble's seed alone), so the result depends only on the spec,
// never on the worker, the thread or the order of evaluations.
#include <cstdint>
#include <string>
#include <vector>

#include "workers/objectives/objective.h"

namespace gaitforge::objectives {

enum class Statistic { kMean, kQuantile, kMeanMinusSd };

struct EnsembleRange {
  std::string name;
  double lo = 0, hi = 0;
  bool log = false;  // sampled uniformly in ln x over [ln lo, ln hi] (needs lo > 0)
};

struct EnsembleSpec {
  int members = 1;
  std::vector<std::string> numerics;  // "" or NAME=VALUE, cycled over the members
  std::vector<EnsembleRange> parameters;
  // Joint samples of `parameters` (each parallel to it); when given, member i takes
  // samples[order[i mod N]] instead of a stratified draw, the order drawn from `seed`.
  std::vector<std::vector<double>> samples;
  int start_phases = 1;
  Statistic statistic = Statistic::kMean;
  double quantile = 0.25;  // kQuantile
  double k = 1;            // kMeanMinusSd
  uint64_t seed = 0;
};

// One member: what it adds to the objective's input.
struct EnsembleMember {
  std::string numeric;            // "" or NAME=VALUE
  double start_phase = 0;         // cycles
  std::vector<double> values;     // parallel to EnsembleSpec::parameters
  // The member's "set" items (numeric variant, then parameter samples), NAME=VALUE,...
  std::string SetText(const EnsembleSpec& spec) const;
};

// "mean", "quantile", "mean_minus_sd"; false for another name.
bool ParseStatistic(const std::string& name, Statistic* out);

// The members, in order (the spec must be valid: members >= 1, lo <= hi).
std::vector<EnsembleMember> Members(const EnsembleSpec& spec);

// The statistic of the values (at least one).
double Combine(std::vector<double> values, const EnsembleSpec& spec);

// Evaluates `input` once per member: the member's set items are appended to the input's
// own "set" option and its start phase is param start_phase. Valid when every member is;
// otherwise the reason names the first invalid member. Metrics: member.I (each member's
// fitness), robust.mean, robust.sd, robust.min, robust.max, robust.members, each of the
// objective's metrics as its mean over the members (simulated_s: the sum).
EvalResult EvaluateEnsemble(const Objective& objective, const EvalInput& input,
                            const EnsembleSpec& spec);

}  // namespace gaitforge::objectives
