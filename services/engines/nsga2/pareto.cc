#include "services/engines/nsga2/pareto.h"

#include <algorithm>
#include <limits>
#include <numeric>

namespace gaitforge::engines::nsga2 {

bool Dominates(const Evaluation& a, const Evaluation& b) {
  if (a.valid != b.valid) return a.valid;
  if (!a.valid) return false;
  const bool fa = a.violation <= 0.0, fb = b.violation <= 0.0;
  if (fa != fb) return fa;
  if (!fa) return a.violation < b.violation;
  bool better = false;
  for (size_t i = 0; i < a.objectives.size() && i < b.objectives.size(); ++i) {
    if (a.objectives[i] < b.objectives[i]) return false;
    better = better || a.objectives[i] > b.objectives[i];
  }
  return better;
}

std::vector<std::vector<int>> NondominatedFronts(const std::vector<Evaluation>& evals) {
  const int n = static_cast<int>(evals.size());
  std::vector<std::vector<int>> dominated(n);  // whom each member dominates
  std::vector<int> dominators(n, 0);           // how many dominate each member
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      if (Dominates(evals[a], evals[b])) {
        dominated[a].push_back(b);
        ++dominators[b];
      } else if (Dominates(evals[b], evals[a])) {
        dominated[b].push_back(a);
        ++dominators[a];
      }
    }
  }
  std::vector<std::vector<int>> fronts;
  std::vector<int> current;
  for (int m = 0; m < n; ++m)
    if (dominators[m] == 0) current.push_back(m);
  while (!current.empty()) {
    std::vector<int> next;
    for (int m : current)
      for (int d : dominated[m])
        if (--dominators[d] == 0) next.push_back(d);
    std::sort(next.begin(), next.end());
    fronts.push_back(std::move(current));
    current = std::move(next);
  }
  return fronts;
}

std::vector<double> CrowdingDistances(const std::vector<Evaluation>& evals,
                                      const std::vector<int>& front) {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> d(front.size(), 0.0);
  std::vector<size_t> valid;  // positions in `front` of its valid members
  for (size_t i = 0; i < front.size(); ++i)
    if (evals[front[i]].valid) valid.push_back(i);
  if (valid.empty()) return d;
  const size_t n_obj = evals[front[valid[0]]].objectives.size();
  for (size_t k = 0; k < n_obj; ++k) {
    std::vector<size_t> order = valid;
    const auto value = [&](size_t i) { return evals[front[i]].objectives[k]; };
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return value(a) < value(b); });
    d[order.front()] = d[order.back()] = inf;
    const double span = value(order.back()) - value(order.front());
    if (span <= 0) continue;
    for (size_t j = 1; j + 1 < order.size(); ++j)
      d[order[j]] += (value(order[j + 1]) - value(order[j - 1])) / span;
  }
  return d;
}

}  // namespace gaitforge::engines::nsga2
