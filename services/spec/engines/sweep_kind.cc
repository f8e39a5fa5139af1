// engine: sweep, a grid, then Nelder-Mead from its best points (services/engines/sweep/).
#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "services/spec/engine_kinds.h"
#include "services/spec/spec_validation.h"
#include "services/engines/sweep/sweep_engine.h"

namespace gaitforge::spec {
namespace {

void Defaults(v1::StudySpec* spec) {
  auto* w = spec->mutable_sweep();
  if (w->points_per_axis_size() == 0) w->add_points_per_axis(5);
  if (!w->has_top_k()) w->set_top_k(3);
  if (!w->has_nm_max_iterations()) w->set_nm_max_iterations(200);
  if (!w->has_nm_tolerance()) w->set_nm_tolerance(1e-8);
  if (!w->has_max_evaluations()) w->set_max_evaluations(0);
}

// sweep.factors: each names genes of the bounds (none in two factors) with one value per
// level inside the gene's bounds, and as many level names as levels (or none). Returns the
// product of the levels, and marks the genes the factors set in `factored`.
double CheckFactors(const v1::StudySpec& spec, std::vector<bool>& factored,
                    std::vector<FieldError>& e) {
  auto add = [&](std::string path, std::string msg) {
    e.push_back({std::move(path), std::move(msg)});
  };
  double product = 1;
  for (int f = 0; f < spec.sweep().factors_size(); ++f) {
    const v1::SweepFactor& factor = spec.sweep().factors(f);
    const std::string at = absl::StrCat("sweep.factors[", f, "]");
    if (factor.genes_size() == 0) add(at + ".genes", "name at least one gene of the bounds");
    const int levels = factor.genes_size() > 0 ? factor.genes(0).values_size() : 0;
    if (factor.genes_size() > 0 && levels == 0)
      add(at + ".genes[0].values", "give at least one level");
    if (factor.levels_size() != 0 && factor.levels_size() != levels)
      add(at + ".levels",
          absl::StrCat("names ", factor.levels_size(), " levels; its genes have ", levels));
    for (int k = 0; k < factor.genes_size(); ++k) {
      const v1::SweepFactorGene& g = factor.genes(k);
      const std::string gat = absl::StrCat(at, ".genes[", k, "]");
      const int i = GeneIndex(spec, g.gene());
      if (i < 0 || factored[i]) {
        add(gat + ".gene",
            absl::StrCat("'", g.gene(),
                         i < 0 ? "' is not a gene of the bounds" : "' is set by another factor"));
        continue;
      }
      factored[i] = true;
      if (g.values_size() != levels)
        add(gat + ".values",
            absl::StrCat("has ", g.values_size(), " values; the factor has ", levels, " levels"));
      for (int l = 0; l < g.values_size(); ++l)
        if (!(g.values(l) >= spec.bounds(i).lo() && g.values(l) <= spec.bounds(i).hi()))
          add(absl::StrCat(gat, ".values[", l, "]"),
              absl::StrCat("= ", g.values(l), " is outside the gene's bounds [",
                           spec.bounds(i).lo(), ", ", spec.bounds(i).hi(), "]"));
    }
    product *= std::max(levels, 1);
  }
  return product;
}

void Check(const v1::StudySpec& spec, std::vector<FieldError>& e) {
  const auto& w = spec.sweep();
  auto add = [&](std::string path, std::string msg) { e.push_back({std::move(path), std::move(msg)}); };
  std::vector<bool> factored(spec.bounds_size(), false);
  double grid = CheckFactors(spec, factored, e);
  if (spec.population() < 0 || spec.population() > 10000000)
    add("population", absl::StrCat("= ", spec.population(),
                                   " is out of range: 0 (whole grid) or [1, 1e7] grid points "
                                   "per generation"));
  if (w.points_per_axis_size() != 1 && w.points_per_axis_size() != spec.bounds_size())
    add("sweep.points_per_axis",
        absl::StrCat("has ", w.points_per_axis_size(), " values; give 1 or one per gene (",
                     spec.bounds_size(), ")"));
  for (int i = 0; i < w.points_per_axis_size(); ++i) {
    const int p = w.points_per_axis(i);
    if (p < 1 || p > 1000)
      add(absl::StrCat("sweep.points_per_axis[", i, "]"),
          absl::StrCat("= ", p, " is out of range [1, 1000]"));
  }
  const bool per_gene = w.points_per_axis_size() == spec.bounds_size();
  for (int i = 0; i < spec.bounds_size(); ++i)
    if (!factored[i] && (per_gene || w.points_per_axis_size() == 1))
      grid *= w.points_per_axis(per_gene ? i : 0);
  if (grid > 1e7)
    add("sweep.points_per_axis", absl::StrCat("make a grid of ", grid, " points; at most 1e7"));
  if (w.top_k() < 0 || w.top_k() > 1000 || (grid >= 1 && w.top_k() > grid))
    add("sweep.top_k",
        absl::StrCat("= ", w.top_k(), " is out of range [0, min(1000, grid size = ", grid, ")]"));
  const double first_batch = spec.population() > 0 ? std::min<double>(spec.population(), grid) : grid;
  const bool population_ok = spec.population() >= 0 && spec.population() <= 10000000;
  if (population_ok && w.max_evaluations() > 0 && w.max_evaluations() < first_batch)
    add("sweep.max_evaluations", absl::StrCat("= ", w.max_evaluations(),
                                              " is below the first grid batch (", first_batch, ")"));
  if (w.nm_max_iterations() < 0 || w.nm_max_iterations() > 1000000)
    add("sweep.nm_max_iterations",
        absl::StrCat("= ", w.nm_max_iterations(), " is out of range [0, 1e6]"));
  if (!(w.nm_tolerance() >= 0 && w.nm_tolerance() < 1))
    add("sweep.nm_tolerance", absl::StrCat("= ", w.nm_tolerance(), " is out of range [0, 1)"));
  if (w.max_evaluations() < 0)
    add("sweep.max_evaluations", absl::StrCat("= ", w.max_evaluations(), " must be >= 0"));
}

absl::StatusOr<std::unique_ptr<engines::Engine>> Make(const v1::StudySpec& spec) {
  const auto& s = spec.sweep();
  engines::sweep::SweepConfig c;
  c.seed = spec.seed();
  c.bounds = BoundsOf(spec);
  c.points_per_axis.assign(s.points_per_axis().begin(), s.points_per_axis().end());
  for (const v1::SweepFactor& f : s.factors()) {
    engines::sweep::Factor factor;
    for (const v1::SweepFactorGene& g : f.genes())
      factor.genes.push_back(GeneIndex(spec, g.gene()));
    const int levels = f.genes_size() > 0 ? f.genes(0).values_size() : 0;
    for (int l = 0; l < levels; ++l) {
      std::vector<double> level;
      for (const v1::SweepFactorGene& g : f.genes()) level.push_back(g.values(l));
      factor.levels.push_back(std::move(level));
    }
    c.factors.push_back(std::move(factor));
  }
  c.top_k = s.top_k();
  c.nm_max_iterations = s.nm_max_iterations();
  c.nm_tolerance = s.nm_tolerance();
  c.grid_batch = spec.population();
  c.max_evaluations = s.max_evaluations();
  auto e = engines::sweep::SweepEngine::Create(c);
  if (!e.ok()) return e.status();
  return std::unique_ptr<engines::Engine>(std::move(*e));
}

int PerGeneration(const v1::StudySpec&, int members) { return std::max(1, members); }

}  // namespace

EngineKind SweepEngineKind() {
  return {"sweep", "sweep", &Defaults, &Check, &Make, &PerGeneration};
}

}  // namespace gaitforge::spec
