#pragma once
// Pareto ranking for multi-objective engines (Deb, Pratap, Agarwal, Meyarivan 2002, "A fast
// and elitist multiobjective genetic algorithm: NSGA-II"): constrained domination, fast
// non-dominated sorting and crowding distance. Objectives are "higher is better".
#include <vector>

#include "services/engines/engine.h"

namespace gaitforge::engines::nsga2 {

// Deb's constrained domination: a valid member dominates an invalid one; a feasible one
// (violation 0) an infeasible one; of two infeasible, the smaller violation dominates; of
// two feasible, a dominates b when it is no worse in every objective and better in one.
// Two invalid members do not dominate each other.
bool Dominates(const Evaluation& a, const Evaluation& b);

// The members in fronts: front 0 is dominated by none, front k only by members of fronts
// before k. Each front lists member indices in increasing order.
std::vector<std::vector<int>> NondominatedFronts(const std::vector<Evaluation>& evals);

// Crowding distance of each member of `front` (same order): per objective, the gap between
// its neighbours in that objective over the front's span, summed; the extremes of each
// objective get infinity. Invalid members get 0. Ties in an objective keep index order.
std::vector<double> CrowdingDistances(const std::vector<Evaluation>& evals,
                                      const std::vector<int>& front);

}  // namespace gaitforge::engines::nsga2
