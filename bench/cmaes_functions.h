#pragma once
// Test functions for the CMA-ES benchmark and tests (minimisation; the engines are given
// fitness = -f), and the benchmark's shared start point, which bench/anchors/deap_cma.py
// reproduces bit for bit (it reimplements core::KeyedRng's SplitMix64).
#include <cmath>
#include <cstdint>
#include <string_view>
#include <vector>

#include "services/core/keyed_rng.h"

namespace gaitforge::bench {

inline double Sphere(const std::vector<double>& x) {
  double f = 0;
  for (double v : x) f += v * v;
  return f;
}

// Axis-parallel ellipsoid with condition number 1e6: sum 10^(6 (i-1)/(n-1)) x_i^2.
inline double Ellipsoid(const std::vector<double>& x) {
  const size_t n = x.size();
  double f = 0;
  for (size_t i = 0; i < n; ++i)
    f += std::pow(1e6, n > 1 ? static_cast<double>(i) / (n - 1) : 0.0) * x[i] * x[i];
  return f;
}

inline double Rosenbrock(const std::vector<double>& x) {
  double f = 0;
  for (size_t i = 0; i + 1 < x.size(); ++i) {
    const double a = x[i + 1] - x[i] * x[i], b = 1.0 - x[i];
    f += 100.0 * a * a + b * b;
  }
  return f;
}

inline double Rastrigin(const std::vector<double>& x) {
  double f = 10.0 * x.size();
  for (double v : x) f += v * v - 10.0 * std::cos(2.0 * M_PI * v);
  return f;
}

using TestFunction = double (*)(const std::vector<double>&);

inline TestFunction FunctionByName(std::string_view name) {
  if (name == "sphere") return Sphere;
  if (name == "ellipsoid") return Ellipsoid;
  if (name == "rosenbrock") return Rosenbrock;
  if (name == "rastrigin") return Rastrigin;
  return nullptr;
}

// The benchmark's x0 for a seed: gene i uniform in [-5, 5) from KeyedRng(seed, 0, i, kInit).
inline std::vector<double> StartPoint(uint64_t seed, int n) {
  std::vector<double> x(n);
  for (int i = 0; i < n; ++i)
    x[i] = core::KeyedRng(seed, 0, i, core::Purpose::kInit).Uniform(-5.0, 5.0);
  return x;
}

}  // namespace gaitforge::bench
