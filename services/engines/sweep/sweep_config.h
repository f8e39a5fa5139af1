#pragma once
// Configuration of the sweep engine (sweep_engine.h): a grid over chosen genes, then
// Nelder-Mead searches seeded at the best grid points.
#include <cstdint>
#include <vector>

#include "services/engines/engine.h"

namespace gaitforge::engines::sweep {

struct SweepConfig {
  // Kept for a uniform engine configuration; the sweep draws no random numbers.
  uint64_t seed = 0;
  Bounds bounds;
  // Grid points per gene: one value for every gene, or one per gene. A gene with p >= 2
  // points is swept over lo + (hi - lo) j / (p - 1), j = 0..p-1 (both faces included); a
  // gene with 1 point is held at the centre of its range during the grid. A circular gene
  // (Bounds::circular) takes lo + (hi - lo) j / p: its faces are one point.
  std::vector<int> points_per_axis = {5};
  // Nelder-Mead searches started at the best top_k grid points (RanksBefore order).
  int top_k = 3;
  // A search ends after nm_max_iterations iterations, or once every vertex of its simplex
  // lies within nm_tolerance of the best vertex in every gene (as a fraction of the range).
  int nm_max_iterations = 200;
  double nm_tolerance = 1e-8;
  // Edge of the initial simplex per gene as a fraction of the range; 0 means one grid
  // spacing on swept genes and 0.1 on held ones.
  double nm_initial_step = 0.0;
  // Grid points per generation; 0 means the whole grid in one generation.
  int grid_batch = 0;
  // Total evaluations; 0 means unlimited. No generation is started that would exceed it.
  int64_t max_evaluations = 0;
};

// Checks a configuration; the message names the field and its allowed range.
absl::Status ValidateSweepConfig(const SweepConfig& config);

// points_per_axis expanded to one value per gene (config must be valid).
std::vector<int> PointsPerGene(const SweepConfig& config);

// Number of grid points (the product of PointsPerGene).
int64_t GridSize(const SweepConfig& config);

}  // namespace gaitforge::engines::sweep
