#include "services/engines/sweep/sweep_config.h"

#include <cmath>

#include "absl/strings/str_cat.h"

namespace gaitforge::engines::sweep {

constexpr int64_t kMaxGrid = 10000000;

absl::Status ValidateSweepConfig(const SweepConfig& c) {
  using absl::InvalidArgumentError;
  using absl::StrCat;
  if (c.bounds.size() == 0 || c.bounds.lo.size() != c.bounds.hi.size())
    return InvalidArgumentError("bounds: at least one gene with lo and hi is required");
  for (size_t i = 0; i < c.bounds.size(); ++i) {
    const double lo = c.bounds.lo[i], hi = c.bounds.hi[i];
    if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo < hi))
      return InvalidArgumentError(
          StrCat("bounds[", i, "]: need finite lo < hi, got lo = ", lo, ", hi = ", hi));
  }
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
  for (int p : PointsPerGene(c)) grid *= p;
  if (grid > kMaxGrid)
    return InvalidArgumentError(StrCat("sweep.points_per_axis: the grid has ", grid,
                                       " points, out of range [1, ", kMaxGrid, "]"));
  if (c.top_k < 1 || c.top_k > 1000 || c.top_k > grid)
    return InvalidArgumentError(StrCat("sweep.top_k = ", c.top_k,
                                       " is out of range [1, min(1000, grid points = ", grid,
                                       ")]"));
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
  if (c.points_per_axis.size() == 1)
    return std::vector<int>(c.bounds.size(), c.points_per_axis[0]);
  return c.points_per_axis;
}

int64_t GridSize(const SweepConfig& c) {
  int64_t n = 1;
  for (int p : PointsPerGene(c)) n *= p;
  return n;
}

}  // namespace gaitforge::engines::sweep
