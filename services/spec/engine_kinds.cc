#include "services/spec/engine_kinds.h"

#include <algorithm>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "services/engines/log_genes.h"

namespace gaitforge::spec {

const std::vector<EngineKind>& EngineKinds() {
  static const std::vector<EngineKind> kinds = {
      GaEngineKind(),     // paper 000's GA (default)
      CmaesEngineKind(),  // CMA-ES with IPOP/BIPOP restarts
      SweepEngineKind(),  // grid, then Nelder-Mead
      Nsga2EngineKind(),  // the Pareto front of several metrics
  };
  return kinds;
}

const EngineKind* FindEngineKind(std::string_view name) {
  for (const auto& k : EngineKinds())
    if (k.name == name) return &k;
  return nullptr;
}

std::string EngineNames() {
  std::vector<std::string> names;
  for (const auto& k : EngineKinds()) names.push_back(k.name);
  return absl::StrJoin(names, ", ");
}

namespace {

// The spec as its engine searches it: every log gene's bounds, CMA-ES start and sweep
// factor values replaced by their logarithms.
v1::StudySpec LogSpace(v1::StudySpec spec) {
  for (int i = 0; i < spec.bounds_size(); ++i) {
    auto* b = spec.mutable_bounds(i);
    if (!b->log()) continue;
    b->set_lo(engines::ToLogSpace(b->lo()));
    b->set_hi(engines::ToLogSpace(b->hi()));
    if (i < spec.cmaes().mean0_size())
      spec.mutable_cmaes()->set_mean0(i, engines::ToLogSpace(spec.cmaes().mean0(i)));
    for (auto& factor : *spec.mutable_sweep()->mutable_factors())
      for (auto& gene : *factor.mutable_genes())
        if (gene.gene() == b->name())
          for (auto& v : *gene.mutable_values()) v = engines::ToLogSpace(v);
  }
  return spec;
}

}  // namespace

absl::StatusOr<std::unique_ptr<engines::Engine>> MakeEngine(const v1::StudySpec& spec) {
  const EngineKind* kind = FindEngineKind(spec.engine());
  if (kind == nullptr)
    return absl::InvalidArgumentError(absl::StrCat("unknown engine '", spec.engine(), "'"));
  std::vector<bool> log;
  for (const auto& b : spec.bounds()) log.push_back(b.log());
  if (std::find(log.begin(), log.end(), true) == log.end()) return kind->make(spec);
  auto inner = kind->make(LogSpace(spec));
  if (!inner.ok()) return inner.status();
  return std::unique_ptr<engines::Engine>(std::make_unique<engines::LogGenesEngine>(
      std::move(*inner), std::move(log), BoundsOf(spec)));
}

int GeneIndex(const v1::StudySpec& spec, const std::string& name) {
  for (int i = 0; i < spec.bounds_size(); ++i)
    if (spec.bounds(i).name() == name) return i;
  return -1;
}

engines::Bounds BoundsOf(const v1::StudySpec& spec) {
  engines::Bounds bounds;
  for (const auto& b : spec.bounds()) {
    bounds.lo.push_back(b.lo());
    bounds.hi.push_back(b.hi());
    bounds.circular.push_back(b.circular());
  }
  return bounds;
}

}  // namespace gaitforge::spec
