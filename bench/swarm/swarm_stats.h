#pragma once
// What the swarm measures on the wire. One per event loop, touched only on its thread;
// merged when the loops have stopped.
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "bench/swarm/event_loop.h"

namespace gaitforge::swarm {

struct CallCount {
  int64_t calls = 0, failed = 0, request_bytes = 0, response_bytes = 0;
};

struct SwarmStats {
  CallCount lease, report, heartbeat, watch;
  int64_t empty_leases = 0;
  int64_t jobs_leased = 0, results_accepted = 0, duplicates = 0, refused = 0;
  int64_t kills = 0;
  std::vector<double> lease_ms;  // round trip of Lease calls that returned jobs
  // Busy intervals (an emulated evaluation's start and end).
  using Intervals = std::vector<std::pair<Clock::time_point, Clock::time_point>>;
  Intervals busy;
  Intervals backup_busy;  // those spent on backup copies of stragglers (also in `busy`)
  // Per study and generation: the last report sent and the first lease of the next one,
  // for the generation turnaround.
  std::map<std::pair<std::string, int>, Clock::time_point> last_report, first_lease;
  // The last lease of a generation's own jobs (not backups): first_lease to it is the time
  // the coordinator took to hand the generation out.
  std::map<std::pair<std::string, int>, Clock::time_point> last_lease;
  // The first report of a generation's results sent.
  std::map<std::pair<std::string, int>, Clock::time_point> first_report;

  // Adds another loop's figures: counts and samples add up, a generation's first times
  // are the earliest and its last times the latest of the loops. Call Close() after the last.
  void Merge(const SwarmStats& o);
  // A generation's last report (a late duplicate of a backup copy, say) is kept at or
  // before the next generation's first lease.
  void Close();

  // Busy seconds inside [from, to].
  static double BusySeconds(const Intervals& xs, Clock::time_point from, Clock::time_point to);
  // Seconds from the last report of generation g to the first lease of g + 1, per
  // generation of every study.
  std::vector<double> TurnaroundsMs() const;
  // Milliseconds from a generation's first lease to the last lease of its own jobs.
  std::vector<double> DispatchSpreadsMs() const;
};

// The q-quantile (0..1) of xs (sorted in place); NaN when empty.
double Quantile(std::vector<double>& xs, double q);

}  // namespace gaitforge::swarm
