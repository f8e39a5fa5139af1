#include "bench/swarm/swarm_stats.h"

#include <algorithm>
#include <cmath>

namespace gaitforge::swarm {

double SwarmStats::BusySeconds(const Intervals& xs, Clock::time_point from,
                               Clock::time_point to) {
  double total = 0;
  for (const auto& [a, b] : xs) {
    const auto s = std::max(a, from), e = std::min(b, to);
    if (e > s) total += std::chrono::duration<double>(e - s).count();
  }
  return total;
}

std::vector<double> SwarmStats::TurnaroundsMs() const {
  std::vector<double> out;
  for (const auto& [key, last] : last_report) {
    auto next = first_lease.find({key.first, key.second + 1});
    if (next == first_lease.end()) continue;
    out.push_back(std::chrono::duration<double, std::milli>(next->second - last).count());
  }
  return out;
}

std::vector<double> SwarmStats::DispatchSpreadsMs() const {
  std::vector<double> out;
  for (const auto& [key, last] : last_lease) {
    auto first = first_lease.find(key);
    if (first == first_lease.end()) continue;
    out.push_back(std::chrono::duration<double, std::milli>(last - first->second).count());
  }
  return out;
}

double Quantile(std::vector<double>& xs, double q) {
  if (xs.empty()) return NAN;
  std::sort(xs.begin(), xs.end());
  const size_t i = std::min(xs.size() - 1, static_cast<size_t>(q * (xs.size() - 1) + 0.5));
  return xs[i];
}

}  // namespace gaitforge::swarm
