#include "services/spec/engine_kinds.h"

#include "absl/strings/str_join.h"

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
