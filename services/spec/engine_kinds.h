#pragma once
// The engines a study may name (spec field `engine`), by name: each kind fills its defaults,
// checks its section of the spec and makes its optimiser. Adding an engine is a file in
// services/spec/engines/ and one line in EngineKinds() (engine_kinds.cc); nothing else
// switches on the engine's name (docs/engines.md).
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/statusor.h"
#include "gaitforge/v1/study.pb.h"
#include "services/engines/engine.h"

namespace gaitforge::spec {

struct FieldError;

inline constexpr int kMaxPopulation = 100000;

struct EngineKind {
  std::string name;     // the spec's `engine`
  std::string section;  // the spec's section of its own settings ("ga", "cmaes", "sweep")
  // Fills what the user may leave out of the section.
  void (*apply_defaults)(v1::StudySpec* spec);
  // Appends every problem of `population` and the section (after ApplyDefaults).
  void (*validate)(const v1::StudySpec& spec, std::vector<FieldError>& errors);
  // The optimiser for a valid spec.
  absl::StatusOr<std::unique_ptr<engines::Engine>> (*make)(const v1::StudySpec& spec);
  // Members evaluated per generation at most (carried members excluded), for ETAs.
  int (*evaluations_per_generation)(const v1::StudySpec& spec, int members);
};

const std::vector<EngineKind>& EngineKinds();
const EngineKind* FindEngineKind(std::string_view name);  // nullptr when unknown
std::string EngineNames();                                // "ga, cmaes, sweep, nsga2"

// The optimiser of a valid spec: its kind's engine, which searches the genes marked `log`
// by their logarithm (engines::LogGenesEngine) while every gene it reports is in the
// spec's units.
absl::StatusOr<std::unique_ptr<engines::Engine>> MakeEngine(const v1::StudySpec& spec);

// Each engine's kind (services/spec/engines/*.cc).
EngineKind GaEngineKind();
EngineKind CmaesEngineKind();
EngineKind SweepEngineKind();
EngineKind Nsga2EngineKind();

// A multi-objective study's objectives of a valid evaluation, each "higher is better" (a
// minimised metric negated), from its metrics; empty for another engine or an invalid
// evaluation. An error names the metric that is missing or not finite.
absl::Status ObjectivesOf(const v1::StudySpec& spec, const v1::Evaluation& e,
                          std::vector<double>* out);

// The spec's bounds as the engines take them.
engines::Bounds BoundsOf(const v1::StudySpec& spec);
// The index of the gene named `name` in the spec's bounds, or -1.
int GeneIndex(const v1::StudySpec& spec, const std::string& name);

}  // namespace gaitforge::spec
