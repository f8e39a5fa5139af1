#pragma once
// The analytic objective family over any search space (the study's bounds; the default
// space is the objective catalog's, services/core/objective_catalog.cc): sphere, ellipsoid, Rosenbrock and Rastrigin of the genes mapped to z in
// [-5, 5), with the optimum shifted off the centre. For tests and benchmarks: exact,
// cheap, and with known optima. docs/objectives.md gives the formulas.
#include <utility>
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

// ZDT1 (Zitzler, Deb, Thiele 2000), two objectives to minimise over genes mapped to
// u in [0, 1]: f1 = u_0, f2 = g (1 - sqrt(f1 / g)) with g = 1 + 9 mean(u_1 ...). Its
// Pareto front is f2 = 1 - sqrt(f1) (all u_i = 0 beyond the first). Objective
// "analytic.zdt1" reports both as metrics f1 and f2, and fitness -(f1 + f2).
std::pair<double, double> Zdt1(const std::vector<double>& u);

}  // namespace gaitforge::objectives
