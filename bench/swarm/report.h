#pragma once
// The swarm's figures as one JSON object (bench/scaling.py reads it).
#include <string>
#include <vector>

#include "bench/swarm/proc_stats.h"
#include "bench/swarm/studies.h"
#include "bench/swarm/swarm_stats.h"

namespace gaitforge::swarm {

// From the first study submitted to the last study's end.
struct RunWindow {
  Clock::time_point start, end;
  double self_cpu0 = 0, self_cpu1 = 0, coord_cpu0 = 0, coord_cpu1 = 0;
  Memory coord_memory;
};

std::string ReportJson(int workers, const std::string& eval, int64_t nofile,
                       const std::vector<std::string>& ids, const std::vector<std::string>& states,
                       const RunWindow& win, SwarmStats& stats, const WatchTraffic& traffic);

}  // namespace gaitforge::swarm
