// engine: ga, the generational GA of paper 000 (services/engines/ga/).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "services/engines/ga/ga_engine.h"
#include "services/spec/engine_kinds.h"
#include "services/spec/spec_validation.h"

namespace gaitforge::spec {
namespace {

void Defaults(v1::StudySpec* spec) {
  auto* ga = spec->mutable_ga();
  if (!ga->has_elite()) ga->set_elite(10);
  if (!ga->has_mutation_rate()) ga->set_mutation_rate(0.10);

}

void Check(const v1::StudySpec& spec, std::vector<FieldError>& e) {
  const bool population_ok = spec.population() >= 2 && spec.population() <= kMaxPopulation;
  if (!population_ok)
    e.push_back({"population", absl::StrCat("= ", spec.population(), " is out of range [2, ",
                                            kMaxPopulation, "]")});
  const auto& ga = spec.ga();
  // Against a bad population the elite's range means nothing: that error is reported.
  if (population_ok && (ga.elite() < 0 || ga.elite() >= spec.population()))
    e.push_back({"ga.elite", absl::StrCat("= ", ga.elite(), " is out of range [0, population - 1 = ",
                                          spec.population() - 1, "]")});
  if (!std::isfinite(ga.mutation_rate()) || ga.mutation_rate() < 0 || ga.mutation_rate() > 1)
    e.push_back({"ga.mutation_rate",
                 absl::StrCat("= ", ga.mutation_rate(), " is out of range [0, 1]")});
  const auto one_of = [&](const char* field, const std::string& value,
                         std::vector<std::string> allowed) {
    if (std::find(allowed.begin(), allowed.end(), value) == allowed.end())
      e.push_back({field, absl::StrCat("= '", value, "' is not one of ", allowed[0], ", ", allowed[1])});
  };
  if (ga.has_selection()) one_of("ga.selection", ga.selection(), {"roulette", "tournament"});
  if (ga.has_crossover()) one_of("ga.crossover", ga.crossover(), {"one_point", "blend"});
  if (ga.has_mutation()) one_of("ga.mutation", ga.mutation(), {"reinit", "gaussian"});
  if (ga.has_stop_fitness() && !std::isfinite(ga.stop_fitness()))
    e.push_back({"ga.stop_fitness", absl::StrCat("= ", ga.stop_fitness(), " is not a finite number")});
}

absl::StatusOr<std::unique_ptr<engines::Engine>> Make(const v1::StudySpec& spec) {
  engines::ga::GaConfig c;
  c.seed = spec.seed();
  c.population = spec.population();
  c.generations = spec.generations();
  c.elite = spec.ga().elite();
  c.mutation_rate = spec.ga().mutation_rate();
  if (spec.ga().has_stop_fitness()) c.stop_fitness = spec.ga().stop_fitness();
  // Unset: paper 000's operators (GaConfig's defaults).
  if (spec.ga().has_selection()) c.selection = spec.ga().selection();
  if (spec.ga().has_crossover()) c.crossover = spec.ga().crossover();
  if (spec.ga().has_mutation()) c.mutation = spec.ga().mutation();
  c.bounds = BoundsOf(spec);
  auto engine = engines::ga::GaEngine::Create(c);
  if (!engine.ok()) return engine.status();
  return std::unique_ptr<engines::Engine>(std::move(*engine));
}

// The elite is carried, not evaluated again.
int PerGeneration(const v1::StudySpec& spec, int members) {
  return std::max(1, members - spec.ga().elite());
}

}  // namespace

EngineKind GaEngineKind() { return {"ga", "ga", &Defaults, &Check, &Make, &PerGeneration}; }

}  // namespace gaitforge::spec
