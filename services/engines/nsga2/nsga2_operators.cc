#include "services/engines/nsga2/nsga2_operators.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace gaitforge::engines::nsga2 {
namespace {

// SBX's spread factor for uniform u: `alpha` is 2 - beta^-(eta + 1) for the bounded form
// (beta: the room to the bound over the parents' gap) and 2 for the unbounded one.
double SpreadFactor(double u, double alpha, double eta) {
  const double e = 1.0 / (eta + 1.0);
  return u <= 1.0 / alpha ? std::pow(u * alpha, e) : std::pow(1.0 / (2.0 - u * alpha), e);
}

// The two children of parents y1 < y2 in [lo, hi] (bounded: lo < hi finite).
std::pair<double, double> SbxPair(double y1, double y2, double lo, double hi, bool bounded,
                                  double eta, double u) {
  const double gap = y2 - y1;
  const auto alpha = [&](double room) {
    return bounded ? 2.0 - std::pow(1.0 + 2.0 * room / gap, -(eta + 1.0)) : 2.0;
  };
  const double c1 = 0.5 * (y1 + y2 - SpreadFactor(u, alpha(y1 - lo), eta) * gap);
  const double c2 = 0.5 * (y1 + y2 + SpreadFactor(u, alpha(hi - y2), eta) * gap);
  return {c1, c2};
}

}  // namespace

void SbxCrossover(std::vector<double>& a, std::vector<double>& b, const Bounds& bounds, double rate,
                  double eta, core::KeyedRng& rng) {
  const bool cross = rng.Uniform01() < rate;
  for (size_t i = 0; i < a.size(); ++i) {
    const double pick = rng.Uniform01(), u = rng.Uniform01(), swap = rng.Uniform01();
    if (!cross || pick >= 0.5) continue;
    const bool circular = bounds.IsCircular(i);
    const double bi = bounds.Near(i, b[i], a[i]);
    if (std::abs(bi - a[i]) <= 1e-14 * (bounds.hi[i] - bounds.lo[i])) continue;
    const double y1 = std::min(a[i], bi), y2 = std::max(a[i], bi);
    auto [c1, c2] = SbxPair(y1, y2, bounds.lo[i], bounds.hi[i], !circular, eta, u);
    if (swap < 0.5) std::swap(c1, c2);
    a[i] = bounds.Fold(i, c1);
    b[i] = bounds.Fold(i, c2);
  }
}

int PolynomialMutation(std::vector<double>& genes, const Bounds& bounds, double rate, double eta,
                       core::KeyedRng& rng) {
  int moved = 0;
  const double e = 1.0 / (eta + 1.0);
  for (size_t i = 0; i < genes.size(); ++i) {
    const double decide = rng.Uniform01(), r = rng.Uniform01();
    if (decide >= rate) continue;
    const double lo = bounds.lo[i], hi = bounds.hi[i], y = genes[i];
    const bool circular = bounds.IsCircular(i);
    // Room to each bound in units of the range (a circle's 1 gives the unbounded step).
    const double d1 = circular ? 1.0 : (y - lo) / (hi - lo);
    const double d2 = circular ? 1.0 : (hi - y) / (hi - lo);
    double dq;
    if (r < 0.5) {
      const double v = 2.0 * r + (1.0 - 2.0 * r) * std::pow(1.0 - d1, eta + 1.0);
      dq = std::pow(v, e) - 1.0;
    } else {
      const double v = 2.0 * (1.0 - r) + 2.0 * (r - 0.5) * std::pow(1.0 - d2, eta + 1.0);
      dq = 1.0 - std::pow(v, e);
    }
    genes[i] = bounds.Fold(i, y + dq * (hi - lo));
    ++moved;
  }
  return moved;
}

}  // namespace gaitforge::engines::nsga2
