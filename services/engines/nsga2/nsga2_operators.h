#pragma once
// NSGA-II's real-coded variation (Deb and Agrawal 1995; Deb and Goyal 1996, as in Deb's
// reference NSGA-II code): simulated binary crossover (SBX) and polynomial mutation, both
// bounded. A circular gene has no bounds: its step is the unbounded one, taken from the
// partner's representative nearest (Bounds::Near) and wrapped back (Bounds::Fold).
// Every call draws a fixed count of numbers per gene, so streams stay keyed.
#include <vector>

#include "services/core/keyed_rng.h"
#include "services/engines/engine.h"

namespace gaitforge::engines::nsga2 {

// With probability `rate` (one number) the pair crosses: each gene, with probability 1/2,
// gets SBX children of spread index `eta` (larger: children nearer their parents), swapped
// between a and b with probability 1/2. Three numbers per gene whether or not it crosses.
void SbxCrossover(std::vector<double>& a, std::vector<double>& b, const Bounds& bounds, double rate,
                  double eta, core::KeyedRng& rng);

// Each gene, with probability `rate`, moves by a polynomial step of distribution index
// `eta` that stays within its range. Two numbers per gene. Returns how many genes moved.
int PolynomialMutation(std::vector<double>& genes, const Bounds& bounds, double rate, double eta,
                       core::KeyedRng& rng);

}  // namespace gaitforge::engines::nsga2
