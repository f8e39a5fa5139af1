// engine: cmaes, CMA-ES with IPOP or BIPOP restarts (services/engines/cmaes/).
#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "services/spec/engine_kinds.h"
#include "services/spec/spec_validation.h"
#include "services/engines/cmaes/cmaes_engine.h"

namespace gaitforge::spec {
namespace {

void Defaults(v1::StudySpec* spec) {
  auto* c = spec->mutable_cmaes();
  if (!c->has_sigma0()) c->set_sigma0(0.3);
  if (!c->has_max_evaluations()) c->set_max_evaluations(100000);
  if (c->restarts().empty()) c->set_restarts("ipop");
  if (!c->has_max_restarts()) c->set_max_restarts(9);
  if (!c->has_tolfun()) c->set_tolfun(1e-12);
  if (!c->has_tolx()) c->set_tolx(1e-12);
}

void Check(const v1::StudySpec& spec, std::vector<FieldError>& e) {
  const auto& c = spec.cmaes();
  auto add = [&](std::string path, std::string msg) { e.push_back({std::move(path), std::move(msg)}); };
  if (spec.population() != 0 && (spec.population() < 4 || spec.population() > 100000))
    add("population", absl::StrCat("= ", spec.population(),
                                   " is out of range: 0 (default lambda) or [4, 100000]"));
  const bool population_ok =
      spec.population() == 0 || (spec.population() >= 4 && spec.population() <= 100000);
  const int n = spec.bounds_size();
  const int lambda = spec.population() != 0
                         ? spec.population()
                         : 4 + static_cast<int>(std::floor(3 * std::log(std::max(n, 1))));
  if (population_ok && c.max_evaluations() < lambda)
    add("cmaes.max_evaluations",
        absl::StrCat("= ", c.max_evaluations(), " is below one generation (lambda = ", lambda,
                     ")"));
  if (!(c.sigma0() > 0 && c.sigma0() <= 1))
    add("cmaes.sigma0", absl::StrCat("= ", c.sigma0(), " is out of range (0, 1]"));
  if (c.mean0_size() != 0 && c.mean0_size() != spec.bounds_size())
    add("cmaes.mean0", absl::StrCat("has ", c.mean0_size(), " values; the space has ",
                                    spec.bounds_size(), " genes"));
  for (int i = 0; i < c.mean0_size() && c.mean0_size() == spec.bounds_size(); ++i) {
    const auto& b = spec.bounds(i);
    if (!(c.mean0(i) >= b.lo() && c.mean0(i) <= b.hi()))
      add(absl::StrCat("cmaes.mean0[", i, "]"),
          absl::StrCat("= ", c.mean0(i), " is outside bounds [", b.lo(), ", ", b.hi(), "]"));
  }
  if (c.max_evaluations() < 1 || c.max_evaluations() > 1000000000000LL)
    add("cmaes.max_evaluations",
        absl::StrCat("= ", c.max_evaluations(), " is out of range [1, 1e12]"));
  if (c.restarts() != "none" && c.restarts() != "ipop" && c.restarts() != "bipop")
    add("cmaes.restarts", absl::StrCat("'", c.restarts(), "' is not one of none, ipop, bipop"));
  if (c.max_restarts() < 0 || c.max_restarts() > 20)
    add("cmaes.max_restarts", absl::StrCat("= ", c.max_restarts(), " is out of range [0, 20]"));
  if (!(c.tolfun() >= 0)) add("cmaes.tolfun", absl::StrCat("= ", c.tolfun(), " must be >= 0"));
  if (!(c.tolx() >= 0)) add("cmaes.tolx", absl::StrCat("= ", c.tolx(), " must be >= 0"));
}

absl::StatusOr<std::unique_ptr<engines::Engine>> Make(const v1::StudySpec& spec) {
  const auto& s = spec.cmaes();
  engines::cmaes::CmaesConfig c;
  c.seed = spec.seed();
  c.bounds = BoundsOf(spec);
  c.mean0.assign(s.mean0().begin(), s.mean0().end());
  c.sigma0_fraction = s.sigma0();
  c.population = spec.population();
  c.max_evaluations = s.max_evaluations();
  c.restarts = engines::cmaes::ParseRestarts(s.restarts()).value_or(engines::cmaes::Restarts::kNone);
  c.max_restarts = s.max_restarts();
  c.tolfun = s.tolfun();
  c.tolx = s.tolx();
  if (s.has_stop_fitness()) c.stop_fitness = s.stop_fitness();
  auto e = engines::cmaes::CmaesEngine::Create(c);
  if (!e.ok()) return e.status();
  return std::unique_ptr<engines::Engine>(std::move(*e));
}

int PerGeneration(const v1::StudySpec&, int members) { return std::max(1, members); }

}  // namespace

EngineKind CmaesEngineKind() {
  return {"cmaes", "cmaes", &Defaults, &Check, &Make, &PerGeneration};
}

}  // namespace gaitforge::spec
