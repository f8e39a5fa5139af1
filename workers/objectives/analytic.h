#pragma once
// The analytic objective family over any search space (the study's bounds; the default
// space is the objective catalog's, services/core/objective_catalog.cc): sphere, ellipsoid, Rosenbrock and Rastrigin of the genes mapped to z in
// [-5, 5), with the optimum shifted off the centre. For tests and benchmarks: exact,
// cheap, and with known optima. docs/objectives.md gives the formulas.
#include <vector>

#include "workers/objectives/objective.h"

namespace gaitforge::objectives {

void RegisterAnalytic(ObjectiveRegistry& registry);

// The loss of each function at z (>= 0, 0 at the optimum z = 0 after the shift; for
// Rosenbrock the optimum is z = 1).
double Sphere(const std::vector<double>& z);
double Ellipsoid(const std::vector<double>& z);
double Rosenbrock(const std::vector<double>& z);
double Rastrigin(const std::vector<double>& z);

}  // namespace gaitforge::objectives
