#pragma once
// Configuration and default strategy parameters of the CMA-ES engine (cmaes_engine.h).
// Equation numbers refer to N. Hansen, "The CMA Evolution Strategy: A Tutorial",
// arXiv:1604.00772 (2016), Appendix A, Table 1 and eqs. (48)-(58).
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include <Eigen/Dense>

#include "services/engines/engine.h"

namespace gaitforge::engines::cmaes {

// What happens when a run meets a stopping criterion (tolfun, tolx, conditioning, ...).
//  kNone:  the engine is done.
//  kIpop:  restart with the population doubled (Auger & Hansen, CEC 2005, "A restart CMA
//          evolution strategy with increasing population size").
//  kBipop: alternate a doubling large-population regime with small-population runs of
//          random size and step size (Hansen, GECCO 2009 BBOB workshop, "Benchmarking a
//          BI-population CMA-ES on the BBOB-2009 function testbed").
enum class Restarts { kNone = 0, kIpop = 1, kBipop = 2 };

// Parses "none" | "ipop" | "bipop".
std::optional<Restarts> ParseRestarts(std::string_view name);
std::string_view RestartsName(Restarts r);

struct CmaesConfig {
  uint64_t seed = 0;
  Bounds bounds;
  // Start of the first run; empty means the box centre. Restarts draw a fresh mean
  // uniformly in the box (as in the IPOP and BIPOP papers).
  std::vector<double> mean0;
  // Initial step size as a fraction of each gene's range (the engine searches the box
  // normalised to [0, 1]^n, so this is sigma0 there). Hansen recommends ~0.3 for a box.
  double sigma0_fraction = 0.3;
  // Offspring per generation lambda; 0 means the default 4 + floor(3 ln n) (eq. 48).
  int population = 0;
  // Total evaluations over all runs; no generation is started that would exceed it.
  int64_t max_evaluations = 100000;
  Restarts restarts = Restarts::kNone;
  int max_restarts = 9;
  // A run stops when the best fitness of the last 10 + ceil(30 n / lambda) generations
  // and all fitness values of the current one span less than tolfun.
  double tolfun = 1e-12;
  // ... or when sigma * sqrt(C_ii) and sigma * p_c,i are below tolx for every i (in the
  // normalised box, so tolx is a fraction of the range).
  double tolx = 1e-12;
  // ... or when the condition number of C exceeds max_condition.
  double max_condition = 1e14;
  // The whole study stops once a feasible fitness >= stop_fitness is seen (optional).
  std::optional<double> stop_fitness;
};

// Checks a configuration; the message names the field and its allowed range.
absl::Status ValidateCmaesConfig(const CmaesConfig& config);

// The default strategy parameters of Table 1 for dimension n and population lambda.
struct StrategyParams {
  int n = 0;
  int lambda = 0;
  int mu = 0;
  Eigen::VectorXd weights;  // all lambda weights, positive then negative (eq. 53)
  double mu_eff = 0;        // variance effective selection mass of the positive weights
  double c_m = 1;           // eq. (54)
  double c_sigma = 0, d_sigma = 0;  // eq. (55)
  double c_c = 0;                   // eq. (56)
  double c1 = 0;                    // eq. (57)
  double c_mu = 0;                  // eq. (58)
  double sum_weights = 0;           // sum of all w_j, for eq. (47)
  double chi_n = 0;                 // E||N(0, I)||, approximation below eq. (44)
};

// lambda = 0 picks the default of eq. (48).
StrategyParams DefaultStrategyParams(int n, int lambda);
int DefaultPopulation(int n);

}  // namespace gaitforge::engines::cmaes
