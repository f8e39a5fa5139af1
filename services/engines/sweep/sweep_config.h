#pragma once
// Configuration of the sweep engine (sweep_engine.h): a grid over chosen genes, then
// Nelder-Mead searches seeded at the best grid points.
#include <cstdint>
#include <vector>

#include "services/engines/engine.h"

namespace gaitforge::engines::sweep {

// A factor of a factorial design: genes that change together, level by level (paper 002's
// gait: a trot's period, stance, lift, ... against a slide's).
struct Factor {
  std::vector<int> genes;                   // gene indexes, each in at most one factor
  std::vector<std::vector<double>> levels;  // levels[l][k]: gene genes[k] at level l
};

struct SweepConfig {
  // Kept for a uniform engine configuration; the sweep draws no random numbers.
  uint64_t seed = 0;
  Bounds bounds;
  // Grid points per gene: one value for every gene, or one per gene. A gene with p >= 2
  // points is swept over lo + (hi - lo) j / (p - 1), j = 0..p-1 (both faces included); a
  // gene with 1 point is held at the centre of its range during the grid. A circular gene
  // (Bounds::circular) takes lo + (hi - lo) j / p: its faces are one point.
  std::vector<int> points_per_axis = {5};
  // A factorial design: the grid is the product of every factor's levels (the first factor
  // varying slowest) and of points_per_axis over the genes no factor sets (varying fastest);
  // points_per_axis is ignored for a factor's genes. Empty: a plain grid.
  std::vector<Factor> factors;
  // Nelder-Mead searches started at the best top_k grid points (RanksBefore order); 0: none,
  // the grid alone.
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

// points_per_axis expanded to one value per gene, 1 for a factor's genes (config must be
// valid).
std::vector<int> PointsPerGene(const SweepConfig& config);

// Number of grid points (the product of PointsPerGene and of the factors' levels).
int64_t GridSize(const SweepConfig& config);

}  // namespace gaitforge::engines::sweep
