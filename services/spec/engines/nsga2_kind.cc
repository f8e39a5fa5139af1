// engine: nsga2, the Pareto front of several metrics (services/engines/nsga2/).
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "services/engines/nsga2/nsga2_engine.h"
#include "services/spec/engine_kinds.h"
#include "services/spec/spec_validation.h"

namespace gaitforge::spec {
namespace {

void Defaults(v1::StudySpec* spec) {
  auto* n = spec->mutable_nsga2();
  if (!n->has_crossover_rate()) n->set_crossover_rate(0.9);
  if (!n->has_crossover_eta()) n->set_crossover_eta(20);
  if (!n->has_mutation_eta()) n->set_mutation_eta(20);
  if (!n->has_mutation_rate() && spec->bounds_size() > 0)
    n->set_mutation_rate(1.0 / spec->bounds_size());
}

void CheckObjectives(const v1::Nsga2Spec& n, std::vector<FieldError>& e) {
  if (n.objectives_size() < 2 || n.objectives_size() > 8)
    e.push_back({"nsga2.objectives",
                 absl::StrCat("has ", n.objectives_size(), " entries; 2 to 8 metrics are needed")});
  std::set<std::string> seen;
  for (int i = 0; i < n.objectives_size(); ++i) {
    const auto& o = n.objectives(i);
    const std::string path = absl::StrCat("nsga2.objectives[", i, "]");
    if (o.metric().empty()) e.push_back({path + ".metric", "is empty: name a metric"});
    if (!seen.insert(o.metric()).second)
      e.push_back({path + ".metric", absl::StrCat("'", o.metric(), "' is named twice")});
    if (o.sense() != "maximize" && o.sense() != "minimize")
      e.push_back(
          {path + ".sense", absl::StrCat("= '", o.sense(), "' is not one of maximize, minimize")});
  }
}

void Check(const v1::StudySpec& spec, std::vector<FieldError>& e) {
  const int max = engines::nsga2::kMaxPopulation;
  if (spec.population() < 4 || spec.population() > max)
    e.push_back(
        {"population", absl::StrCat("= ", spec.population(), " is out of range [4, ", max, "]")});
  const auto& n = spec.nsga2();
  CheckObjectives(n, e);
  const auto in = [&](const char* field, double v, double lo, double hi) {
    if (!(v >= lo && v <= hi))
      e.push_back({field, absl::StrCat("= ", v, " is out of range [", lo, ", ", hi, "]")});
  };
  in("nsga2.crossover_rate", n.crossover_rate(), 0, 1);
  in("nsga2.crossover_eta", n.crossover_eta(), 0, 1000);
  in("nsga2.mutation_rate", n.mutation_rate(), 0, 1);
  in("nsga2.mutation_eta", n.mutation_eta(), 0, 1000);
}

absl::StatusOr<std::unique_ptr<engines::Engine>> Make(const v1::StudySpec& spec) {
  engines::nsga2::Nsga2Config c;
  c.seed = spec.seed();
  c.population = spec.population();
  c.generations = spec.generations();
  c.objectives = spec.nsga2().objectives_size();
  c.crossover_rate = spec.nsga2().crossover_rate();
  c.crossover_eta = spec.nsga2().crossover_eta();
  c.mutation_rate = spec.nsga2().mutation_rate();
  c.mutation_eta = spec.nsga2().mutation_eta();
  c.bounds = BoundsOf(spec);
  auto engine = engines::nsga2::Nsga2Engine::Create(c);
  if (!engine.ok()) return engine.status();
  return std::unique_ptr<engines::Engine>(std::move(*engine));
}

int PerGeneration(const v1::StudySpec&, int members) { return members; }

}  // namespace

EngineKind Nsga2EngineKind() {
  return {"nsga2", "nsga2", &Defaults, &Check, &Make, &PerGeneration};
}

absl::Status ObjectivesOf(const v1::StudySpec& spec, const v1::Evaluation& e,
                          std::vector<double>* out) {
  out->clear();
  if (!e.valid()) return absl::OkStatus();  // only nsga2 has objectives (a section of its own)
  for (int i = 0; i < spec.nsga2().objectives_size(); ++i) {
    const auto& o = spec.nsga2().objectives(i);
    auto it = e.metrics().find(o.metric());
    if (it == e.metrics().end() || !std::isfinite(it->second))
      return absl::InvalidArgumentError(
          absl::StrCat("metric '", o.metric(), "' (nsga2.objectives[", i, "]) ",
                       it == e.metrics().end() ? "was not reported" : "is not a finite number"));
    out->push_back(o.sense() == "minimize" ? -it->second : it->second);
  }
  return absl::OkStatus();
}

}  // namespace gaitforge::spec
