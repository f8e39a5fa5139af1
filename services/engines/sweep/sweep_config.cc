#include "services/engines/sweep/sweep_config.h"

#include <cmath>
#include <string>

#include "absl/strings/str_cat.h"

namespace gaitforge::engines::sweep {

constexpr int64_t kMaxGrid = 10000000;

namespace {

// Every factor sets genes of the bounds, none twice, with one value per gene at each of its
// levels, inside the gene's bounds.
absl::Status ValidateFactors(const SweepConfig& c) {
  using absl::StrCat;
  std::vector<bool> taken(c.bounds.size(), false);
  for (size_t f = 0; f < c.factors.size(); ++f) {
    const Factor& factor = c.factors[f];
    const std::string at = StrCat("sweep.factors[", f, "]");
    if (factor.genes.empty() || factor.levels.empty())
      return absl::InvalidArgumentError(at + ": needs at least one gene and one level");
    for (int g : factor.genes) {
      if (g < 0 || static_cast<size_t>(g) >= c.bounds.size() || taken[g])
        return absl::InvalidArgumentError(
            StrCat(at, ": gene ", g, " is not a gene of the bounds, or is set by two factors"));
      taken[g] = true;
    }
    for (size_t l = 0; l < factor.levels.size(); ++l) {
      if (factor.levels[l].size() != factor.genes.size())
        return absl::InvalidArgumentError(StrCat(at, ": level ", l, " has ",
                                                 factor.levels[l].size(), " values for ",
                                                 factor.genes.size(), " genes"));
      for (size_t k = 0; k < factor.genes.size(); ++k) {
        const int g = factor.genes[k];
        const double v = factor.levels[l][k];
        if (!(v >= c.bounds.lo[g] && v <= c.bounds.hi[g]))
          return absl::InvalidArgumentError(StrCat(at, ": level ", l, " puts gene ", g, " at ", v,
                                                   ", outside its bounds [", c.bounds.lo[g], ", ",
                                                   c.bounds.hi[g], "]"));
      }
    }
  }
  return absl::OkStatus();
}

}  // namespace

absl::Status ValidateSweepConfig(const SweepConfig& c) {
  using absl::InvalidArgumentError;
  using absl::StrCat;
  if (auto s = ValidateBounds(c.bounds); !s.ok()) return s;
  if (c.points_per_axis.size() != 1 && c.points_per_axis.size() != c.bounds.size())
    return InvalidArgumentError(StrCat("sweep.points_per_axis has ", c.points_per_axis.size(),
                                       " values, expected 1 or one per gene (",
                                       c.bounds.size(), ")"));
  double grid = 1;
  for (size_t i = 0; i < c.points_per_axis.size(); ++i) {
    const int p = c.points_per_axis[i];
    if (p < 1 || p > 10000)
      return InvalidArgumentError(
          StrCat("sweep.points_per_axis[", i, "] = ", p, " is out of range [1, 10000]"));
  }
  if (absl::Status s = ValidateFactors(c); !s.ok()) return s;
  for (int p : PointsPerGene(c)) grid *= p;
  for (const Factor& f : c.factors) grid *= static_cast<double>(f.levels.size());
  if (grid > kMaxGrid)
    return InvalidArgumentError(StrCat("sweep.points_per_axis: the grid has ", grid,
                                       " points, out of range [1, ", kMaxGrid, "]"));
  if (c.top_k < 0 || c.top_k > 1000 || c.top_k > grid)
    return InvalidArgumentError(StrCat(
        "sweep.top_k = ", c.top_k, " is out of range [0, min(1000, grid points = ", grid, ")]"));
  if (c.nm_max_iterations < 0 || c.nm_max_iterations > 1000000)
    return InvalidArgumentError(StrCat("sweep.nm_max_iterations = ", c.nm_max_iterations,
                                       " is out of range [0, 1000000]"));
  if (!(c.nm_tolerance >= 0.0 && c.nm_tolerance < 1.0))
    return InvalidArgumentError(
        StrCat("sweep.nm_tolerance = ", c.nm_tolerance, " is out of range [0, 1)"));
  if (!(c.nm_initial_step >= 0.0 && c.nm_initial_step <= 1.0))
    return InvalidArgumentError(
        StrCat("sweep.nm_initial_step = ", c.nm_initial_step, " is out of range [0, 1]"));
  if (c.grid_batch < 0)
    return InvalidArgumentError(
        StrCat("sweep.grid_batch = ", c.grid_batch, " is out of range [0 (whole grid), inf)"));
  if (c.max_evaluations < 0)
    return InvalidArgumentError(StrCat("sweep.max_evaluations = ", c.max_evaluations,
                                       " is out of range [0 (unlimited), inf)"));
  return absl::OkStatus();
}

std::vector<int> PointsPerGene(const SweepConfig& c) {
  std::vector<int> points = c.points_per_axis.size() == 1
                                ? std::vector<int>(c.bounds.size(), c.points_per_axis[0])
                                : c.points_per_axis;
  for (const Factor& f : c.factors)
    for (int g : f.genes) points[g] = 1;
  return points;
}

int64_t GridSize(const SweepConfig& c) {
  int64_t n = 1;
  for (int p : PointsPerGene(c)) n *= p;
  for (const Factor& f : c.factors) n *= static_cast<int64_t>(f.levels.size());
  return n;
}

}  // namespace gaitforge::engines::sweep
