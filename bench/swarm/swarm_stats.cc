#include "bench/swarm/swarm_stats.h"

#include <algorithm>
#include <cmath>

namespace gaitforge::swarm {

namespace {

using TimeMap = std::map<std::pair<std::string, int>, Clock::time_point>;

void MergeTimes(TimeMap& into, const TimeMap& from, bool earliest) {
  for (const auto& [key, t] : from) {
    auto [it, fresh] = into.emplace(key, t);
    if (!fresh) it->second = earliest ? std::min(it->second, t) : std::max(it->second, t);
  }
}

void Add(CallCount& a, const CallCount& b) {
  a.calls += b.calls;
  a.failed += b.failed;
  a.request_bytes += b.request_bytes;
  a.response_bytes += b.response_bytes;
}

}  // namespace

void SwarmStats::Merge(const SwarmStats& o) {
  Add(lease, o.lease);
  Add(report, o.report);
  Add(heartbeat, o.heartbeat);
  Add(watch, o.watch);
  empty_leases += o.empty_leases;
  jobs_leased += o.jobs_leased;
  results_accepted += o.results_accepted;
  duplicates += o.duplicates;
  refused += o.refused;
  kills += o.kills;
  lease_ms.insert(lease_ms.end(), o.lease_ms.begin(), o.lease_ms.end());
  busy.insert(busy.end(), o.busy.begin(), o.busy.end());
  backup_busy.insert(backup_busy.end(), o.backup_busy.begin(), o.backup_busy.end());
  MergeTimes(first_lease, o.first_lease, true);
  MergeTimes(first_report, o.first_report, true);
  MergeTimes(last_lease, o.last_lease, false);
  MergeTimes(last_report, o.last_report, false);
}

void SwarmStats::Close() {
  for (auto& [key, t] : last_report) {
    auto next = first_lease.find({key.first, key.second + 1});
    if (next != first_lease.end()) t = std::min(t, next->second);
  }
}

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
