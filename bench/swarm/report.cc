#include "bench/swarm/report.h"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"

namespace gaitforge::swarm {
namespace {

std::string Num(double x) { return std::isfinite(x) ? absl::StrCat(x) : "null"; }

std::string Calls(const CallCount& c, double secs) {
  return absl::StrCat("{\"calls\": ", c.calls, ", \"failed\": ", c.failed,
                      ", \"request_bytes\": ", c.request_bytes, ", \"response_bytes\": ",
                      c.response_bytes, ", \"per_second\": ", Num(c.calls / secs), "}");
}

double MsSince(Clock::time_point from, const std::map<std::pair<std::string, int>, Clock::time_point>& m,
               const std::pair<std::string, int>& key) {
  auto it = m.find(key);
  return it == m.end() ? NAN : std::chrono::duration<double, std::milli>(it->second - from).count();
}

// The first study's generations: when each was first and last leased and first and last
// reported, in ms from the submission (where a generation's barrier time goes).
std::string Timeline(const std::string& study, const RunWindow& win, const SwarmStats& st) {
  std::vector<std::string> rows;
  for (int g = 0;; ++g) {
    const auto key = std::make_pair(study, g);
    if (!st.first_lease.count(key)) break;
    rows.push_back(absl::StrCat("[", g, ", ", Num(MsSince(win.start, st.first_lease, key)), ", ",
                                Num(MsSince(win.start, st.last_lease, key)), ", ",
                                Num(MsSince(win.start, st.first_report, key)), ", ",
                                Num(MsSince(win.start, st.last_report, key)), "]"));
  }
  return absl::StrCat("[", absl::StrJoin(rows, ", "), "]");
}

}  // namespace

std::string ReportJson(int workers, const std::string& eval, int64_t nofile,
                       const std::vector<std::string>& ids, const std::vector<std::string>& states,
                       const RunWindow& win, SwarmStats& st, const WatchTraffic& traffic) {
  const double wall = std::chrono::duration<double>(win.end - win.start).count();
  const double busy = SwarmStats::BusySeconds(st.busy, win.start, win.end);
  const double backup = SwarmStats::BusySeconds(st.backup_busy, win.start, win.end);
  std::vector<double> turn = st.TurnaroundsMs(), spread = st.DispatchSpreadsMs();
  const double coord_cpu = win.coord_cpu1 - win.coord_cpu0;
  std::vector<std::string> quoted_ids, quoted_states;
  for (const auto& id : ids) quoted_ids.push_back(absl::StrCat("\"", id, "\""));
  for (const auto& s : states) quoted_states.push_back(absl::StrCat("\"", s, "\""));
  const double accepted = static_cast<double>(st.results_accepted);
  return absl::StrCat(
      "{\"workers\": ", workers, ", \"eval\": \"", eval, "\", \"studies\": ", ids.size(),
      ", \"study_ids\": [", absl::StrJoin(quoted_ids, ", "), "], \"states\": [",
      absl::StrJoin(quoted_states, ", "), "], \"open_file_limit\": ", nofile,
      ",\n \"wall_s\": ", Num(wall), ", \"busy_worker_s\": ", Num(busy),
      ", \"efficiency\": ", Num(busy / (workers * wall)), ", \"backup_worker_s\": ", Num(backup),
      ", \"useful_efficiency\": ", Num((busy - backup) / (workers * wall)),
      ",\n \"results_accepted\": ", st.results_accepted, ", \"duplicates\": ", st.duplicates,
      ", \"refused\": ", st.refused, ", \"jobs_leased\": ", st.jobs_leased,
      ", \"empty_leases\": ", st.empty_leases, ", \"kills\": ", st.kills,
      ",\n \"lease_ms_p50\": ", Num(Quantile(st.lease_ms, 0.5)),
      ", \"lease_ms_p99\": ", Num(Quantile(st.lease_ms, 0.99)),
      ", \"turnaround_ms_p50\": ", Num(Quantile(turn, 0.5)),
      ", \"turnaround_ms_p99\": ", Num(Quantile(turn, 0.99)),
      ", \"dispatch_ms_p50\": ", Num(Quantile(spread, 0.5)),
      ", \"dispatch_ms_p99\": ", Num(Quantile(spread, 0.99)),
      ",\n \"coordinator_cpu_s\": ", Num(coord_cpu),
      ", \"coordinator_cpu_us_per_eval\": ", Num(accepted > 0 ? 1e6 * coord_cpu / accepted : NAN),
      ", \"coordinator_rss_mib\": ", Num(win.coord_memory.rss_mib),
      ", \"coordinator_peak_mib\": ", Num(win.coord_memory.peak_mib),
      ", \"swarm_cpu_s\": ", Num(win.self_cpu1 - win.self_cpu0),
      ",\n \"lease\": ", Calls(st.lease, wall), ", \"report\": ", Calls(st.report, wall),
      ", \"heartbeat\": ", Calls(st.heartbeat, wall),
      ",\n \"watch\": {\"messages\": ", traffic.messages.load(), ", \"bytes\": ",
      traffic.bytes.load(), ", \"reconnects\": ", traffic.reconnects.load(), "}",
      ",\n \"timeline_columns\": [\"generation\", \"first_lease_ms\", \"last_lease_ms\", "
      "\"first_report_ms\", \"last_report_ms\"], \"timeline\": ",
      ids.empty() ? "[]" : Timeline(ids[0], win, st), "}");
}

}  // namespace gaitforge::swarm
