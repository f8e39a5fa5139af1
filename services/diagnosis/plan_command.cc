// gaitforge-sim plan's command line for a diagnosis (plan_command.h).
#include "services/diagnosis/plan_command.h"

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "services/core/subprocess.h"

namespace gaitforge::diagnosis {

std::vector<std::string> PlanCommand(const v1::DiagnosisSpec& d, const std::string& robot,
                                     const std::vector<std::string>& recordings,
                                     plan::Options o, const plan::ReportModel& m) {
  if (auto it = d.params().find("max_shift_samples"); it != d.params().end())
    o.max_shift = static_cast<int>(it->second);
  std::vector<std::string> argv = {core::SiblingBinary("gaitforge-sim"), "plan", "--robot", robot,
                                   "--recordings", absl::StrJoin(recordings, ",")};
  for (const std::string& a : plan::Arguments(o)) argv.push_back(a);
  std::vector<std::string> counts;
  for (const auto& [name, n] : m.counts) counts.push_back(absl::StrCat(name, "=", n));
  if (!counts.empty()) argv.insert(argv.end(), {"--count", absl::StrJoin(counts, ",")});
  const double ms = m.timestep_ms > 0 ? m.timestep_ms : d.has_timestep_ms() ? d.timestep_ms() : 0;
  if (ms > 0)
    argv.insert(argv.end(), {"--set", absl::StrFormat("simulation.timestep_s=%.17g", ms / 1000)});
  if (!d.channels().empty()) argv.insert(argv.end(), {"--channels", d.channels()});
  return argv;
}

}  // namespace gaitforge::diagnosis
