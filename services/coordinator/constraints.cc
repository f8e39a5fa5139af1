#include "services/coordinator/constraints.h"

namespace gaitforge::coordinator {

double Violation(const v1::StudySpec& spec, bool valid,
                 const std::map<std::string, double>& metrics) {
  if (!valid) return 0.0;
  double total = 0.0;
  for (const auto& c : spec.constraints()) {
    auto it = metrics.find(c.metric());
    if (it == metrics.end()) {
      total += 1e30;
      continue;
    }
    const double v = it->second;
    double excess = 0.0;
    if (c.has_min() && v < c.min()) excess = c.min() - v;
    if (c.has_max() && v > c.max()) excess = v - c.max();
    total += excess / (c.scale() > 0 ? c.scale() : 1.0);
  }
  return total;
}

}  // namespace gaitforge::coordinator
