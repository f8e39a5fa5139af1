// gaitforge export: a hall-of-fame gait as the command timeline a real robot's controller
// plays (docs/cli.md, "export"): the controller's commands of the study's robot sampled at
// a rate over whole cycles, and for on/off actuators the switching windows of one cycle.
#include <cmath>
#include <fstream>
#include <iostream>

#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "clients/cli/cli.h"
#include "robots/controllers.h"
#include "services/core/objective_catalog.h"

namespace gaitforge::cli {
namespace {

// One actuator's ON windows within a cycle, [on_s, off_s) in seconds from the cycle start.
std::vector<std::pair<double, double>> OnWindows(const std::vector<double>& genes, size_t k) {
  const size_t n = (genes.size() - 1) / 2;
  const double period = genes.back();
  const double a = genes[k] - std::floor(genes[k]), d = genes[n + k] - std::floor(genes[n + k]);
  if (a == d) return {};
  if (a < d) return {{a * period, d * period}};
  std::vector<std::pair<double, double>> w;
  if (d > 0) w.push_back({0, d * period});
  w.push_back({a * period, period});
  return w;
}

// The fastest set-point change per actuator over the timeline (units of the command per s).
std::vector<double> MaxRates(const std::vector<std::vector<double>>& rows, double rate) {
  std::vector<double> out(rows.empty() ? 0 : rows[0].size(), 0.0);
  for (size_t i = 1; i < rows.size(); ++i)
    for (size_t k = 0; k < out.size(); ++k)
      out[k] = std::max(out[k], std::abs(rows[i][k] - rows[i - 1][k]) * rate);
  return out;
}

// The servos' speed limits (rad/s) at the descriptor's nominal values, per controller
// actuator; NaN where the actuator states none.
std::vector<double> SpeedLimits(const robots::RobotDescriptor& d) {
  const auto value = [&d](const std::string& n) { return d.FindParameter(n)->value; };
  std::vector<double> out;
  for (const std::string& name : d.controller.actuators) {
    double limit = NAN;
    for (const auto& a : d.actuators)
      if (a.name == name && a.type == "servo" && !a.kp) limit = a.max_speed.Eval(value);
    out.push_back(limit);
  }
  return out;
}

void PrintJson(const std::string& id, int rank, const robots::RobotDescriptor& d,
               const std::vector<double>& genes, double period, double rate, size_t samples,
               const std::string& out, const std::vector<double>& rates,
               const std::vector<double>& limits) {
  std::cout << "{\"study_id\":" << JsonQuote(id) << ",\"rank\":" << rank
            << ",\"robot\":" << JsonQuote(d.name) << ",\"controller\":" << JsonQuote(d.controller.kind)
            << absl::StrFormat(",\"period_s\":%.17g,\"rate_hz\":%.17g", period, rate)
            << ",\"samples\":" << samples << ",\"file\":" << JsonQuote(out) << ",\"actuators\":[";
  for (size_t k = 0; k < d.controller.actuators.size(); ++k) {
    std::cout << (k ? "," : "") << "{\"name\":" << JsonQuote(d.controller.actuators[k]);
    if (d.controller.kind == "phase_onoff") {
      std::vector<std::string> w;
      for (const auto& [on, off] : OnWindows(genes, k))
        w.push_back(absl::StrFormat("[%.17g,%.17g]", on, off));
      std::cout << ",\"on_windows_s\":[" << absl::StrJoin(w, ",") << "]";
    } else {
      std::cout << absl::StrFormat(",\"max_rate_per_s\":%.17g", rates[k]);
      if (!std::isnan(limits[k])) std::cout << absl::StrFormat(",\"max_speed_rad_per_s\":%.17g", limits[k]);
    }
    std::cout << "}";
  }
  std::cout << "]}\n";
}

}  // namespace

int CmdExport(const GlobalOptions& g, const std::vector<std::string>& args, int rank,
              int generation, const std::string& out, double rate, int cycles) {
  if (args.size() != 1 || out.empty() || !(rate > 0 && rate <= 1e5) || cycles < 1 || cycles > 1000) {
    std::cerr << "gaitforge: usage: gaitforge export STUDY_ID --output FILE.csv [--rank R] "
                 "[--generation G] [--rate HZ (0..1e5]] [--cycles N (1..1000)]\n";
    return kUsage;
  }
  v1::Individual ind;
  v1::StudySummary study;
  if (int code = RankedGait(g, args[0], generation, rank, "export", &ind, &study); code != kOk)
    return code;
  const auto& o = study.spec().objective();
  const core::ObjectiveInfo* info = core::FindObjective(o.name());
  auto robot = info && !info->calibration
                   ? core::RobotOfObjective(*info, o.robot(), o.robot_descriptor())
                   : absl::InvalidArgumentError(o.name() + " evolves no gait");
  if (!robot.ok()) {
    std::cerr << "gaitforge: export " << args[0] << ": " << robot.status().message() << "\n";
    return kUsage;
  }
  const robots::RobotDescriptor& d = **robot;
  const robots::ControllerKind* kind = robots::FindControllerKind(d.controller.kind);
  // The gait's genes; a study may append body genes (docs/robots.md), which no command uses.
  const size_t n = std::min<size_t>(ind.genes_size(), d.controller.genes.size());
  const std::vector<double> genes(ind.genes().begin(), ind.genes().begin() + n);
  const double period = kind->period_s(genes);
  const size_t samples = static_cast<size_t>(std::floor(cycles * period * rate + 1e-9)) + 1;
  std::vector<std::vector<double>> rows;
  robots::ControllerRun run(d.controller, genes);
  for (size_t i = 0; i < samples; ++i) rows.push_back(run.At(i / rate));
  std::ofstream file(out);
  file << "t," << absl::StrJoin(d.controller.actuators, ",") << "\n";
  for (size_t i = 0; i < samples; ++i) {
    file << absl::StrFormat("%.6f", i / rate);
    for (double v : rows[i]) file << absl::StrFormat(",%.9g", v);
    file << "\n";
  }
  if (!file) {
    std::cerr << "gaitforge: export: cannot write '" << out << "'\n";
    return kFailed;
  }
  const std::vector<double> rates = MaxRates(rows, rate), limits = SpeedLimits(d);
  for (size_t k = 0; k < rates.size(); ++k)
    if (!std::isnan(limits[k]) && rates[k] > limits[k])
      std::cerr << "gaitforge: warning: " << d.controller.actuators[k] << "'s set-point moves at up to "
                << rates[k] << " rad/s, beyond its servo's " << limits[k] << " rad/s\n";
  if (g.json) PrintJson(args[0], rank, d, genes, period, rate, samples, out, rates, limits);
  else std::cout << out << "\n";
  return kOk;
}

}  // namespace gaitforge::cli
