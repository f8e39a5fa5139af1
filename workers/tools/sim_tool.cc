#include "workers/tools/sim_tool.h"

#include "workers/objectives/overrides.h"

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_split.h"
#include "robots/controllers.h"
#include "robots/onoff_waves.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::simtool {

std::string JsonEscape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {
      out += absl::StrFormat("\\u%04x", c);
      continue;
    }
    out += c;
  }
  return out;
}

void ParallelFor(int n, int threads, const std::function<void(int)>& fn) {
  std::atomic<int> next{0};
  std::vector<std::thread> pool;
  for (int t = 0; t < std::max(1, threads); ++t) {
    pool.emplace_back([&] {
      sim::InitThread();
      for (int i = next++; i < n; i = next++) fn(i);
    });
  }
  for (auto& t : pool) t.join();
}

absl::Status WriteChannels(const calibration::Trajectory& tr, const std::string& csv_path,
                           const std::string& robot, const std::string& params_path,
                           const std::vector<double>& genes, const std::string& note,
                           const std::vector<std::pair<std::string, double>>& overrides,
                           bool playback) {
  std::ofstream csv(csv_path);
  if (!csv) return absl::UnavailableError(absl::StrCat("cannot write ", csv_path));
  csv << "t";
  for (const auto& c : tr.channels) csv << "," << c;
  csv << "\n";
  for (size_t k = 0; k < tr.t.size(); ++k) {
    csv << absl::StrFormat("%.6f", tr.t[k]);
    for (const auto& col : tr.columns) csv << absl::StrFormat(",%.9g", col[k]);
    csv << "\n";
  }
  std::ofstream side(csv_path + ".json");
  side << "{\n  \"robot\": \"" << JsonEscape(robot) << "\",\n  \"parameters\": \""
       << JsonEscape(params_path) << "\",\n  \"command\": ";
  if (playback) {
    side << "{\"kind\": \"playback\"},\n";
  } else {
    side << "{\"kind\": \"gait\", \"genes\": [";
    for (size_t i = 0; i < genes.size(); ++i) side << (i ? ", " : "") << absl::StrFormat("%.17g", genes[i]);
    side << "]},\n";
  }
  if (!overrides.empty()) {
    side << "  \"overrides\": {";
    for (size_t i = 0; i < overrides.size(); ++i)
      side << (i ? ", " : "") << "\"" << JsonEscape(overrides[i].first)
           << "\": " << absl::StrFormat("%.17g", overrides[i].second);
    side << "},\n";
  }
  side << "  \"source\": \"simulation\",\n  \"note\": \"" << JsonEscape(note) << "\"\n}\n";
  if (!csv || !side) return absl::DataLossError(absl::StrCat("write failed: ", csv_path));
  return absl::OkStatus();
}

absl::StatusOr<std::vector<SweepPoint>> PeriodSweep(const robots::RobotDescriptor& d,
                                                    const generic::ParamValues& values,
                                                    const std::vector<double>& genes,
                                                    const std::vector<double>& scales,
                                                    const generic::GaitOptions& options,
                                                    int threads) {
  int period = -1, frequency = -1;
  for (size_t k = 0; k < d.controller.genes.size(); ++k) {
    if (d.controller.genes[k].name == "T") period = static_cast<int>(k);
    if (d.controller.genes[k].name == "f") frequency = static_cast<int>(k);
  }
  if (period < 0 && frequency < 0)
    return absl::InvalidArgumentError(absl::StrCat(
        "period-sweep: ", d.name, "'s controller (", d.controller.kind,
        ") has no period gene T or frequency gene f"));
  std::vector<SweepPoint> out(scales.size());
  ParallelFor(static_cast<int>(scales.size()), threads, [&](int i) {
    std::vector<double> g = genes;
    if (period >= 0) {
      g[period] = genes[period] * scales[i];
    } else {
      g[frequency] = genes[frequency] / scales[i];
    }
    out[i].scale = scales[i];
    out[i].period_s = robots::FindControllerKind(d.controller.kind)->period_s(g);
    out[i].eval = generic::EvaluateGait(d, values, g, options);
  });
  return out;
}

absl::StatusOr<std::vector<SweepPoint>> WaveSweep(const robots::RobotDescriptor& d,
                                                  const generic::ParamValues& values,
                                                  const std::vector<double>& periods,
                                                  const generic::GaitOptions& options,
                                                  int threads) {
  const int actuators = static_cast<int>(d.controller.actuators.size());
  if (d.controller.kind != "phase_onoff" || actuators < 2 || actuators % 2 != 0)
    return absl::InvalidArgumentError(absl::StrCat(
        "wave: the travelling waves need a phase_onoff controller over two rows of actuators; ",
        d.name, "'s is ", d.controller.kind, " over ", actuators));
  const auto& family = robots::WaveFamily();
  const int np = static_cast<int>(periods.size());
  std::vector<SweepPoint> out(family.size() * periods.size());
  ParallelFor(static_cast<int>(out.size()), threads, [&](int i) {
    const robots::WaveShape& shape = family[i / np];
    out[i].period_s = periods[i % np];
    out[i].shape = shape.Name();
    out[i].eval = generic::EvaluateGait(d, values, robots::WaveGenes(actuators, out[i].period_s, shape),
                                        options);
  });
  return out;
}

std::string SweepJson(const std::vector<SweepPoint>& points) {
  std::string out = "[";
  for (size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    absl::StrAppend(&out, i ? ",\n " : "",
                    p.shape.empty() ? "" : absl::StrCat("{\"shape\": \"", p.shape, "\", "),
                    absl::StrFormat("%s\"scale\": %.6g, \"period_s\": %.9g, \"valid\": %s, "
                                    "\"distance_per_cycle_m\": %.9g, \"airborne_fraction\": %.6g, "
                                    "\"actuator_energy_j\": %.6g, \"reason\": \"%s\"}",
                                    p.shape.empty() ? "{" : "", p.scale, p.period_s,
                                    p.eval.valid ? "true" : "false",
                                    p.eval.valid ? p.eval.distance_per_cycle_m : 0.0,
                                    p.eval.airborne_fraction, p.eval.piston_work_j,
                                    JsonEscape(p.eval.reason)));
  }
  return out + "]";
}

absl::StatusOr<std::vector<std::pair<std::string, double>>> ParseOverrides(
    const std::string& text) {
  return objectives::ParseOverrides(text);
}

absl::StatusOr<std::map<std::string, std::string>> ParseOptions(const std::string& text) {
  std::map<std::string, std::string> out;
  for (const auto& part : absl::StrSplit(text, ';', absl::SkipEmpty())) {
    const std::string s(part);
    const size_t eq = s.find('=');
    if (eq == std::string::npos || eq == 0)
      return absl::InvalidArgumentError(absl::StrCat("'", s, "': expected NAME=VALUE"));
    out[s.substr(0, eq)] = s.substr(eq + 1);
  }
  return out;
}

absl::StatusOr<std::vector<double>> ParseRange(const std::string& text, bool geometric) {
  std::vector<std::string> parts = absl::StrSplit(text, ',');
  if (parts.size() != 3)
    return absl::InvalidArgumentError(absl::StrCat("expected FROM,TO,COUNT, got '", text, "'"));
  char* end;
  const double a = std::strtod(parts[0].c_str(), &end), b = std::strtod(parts[1].c_str(), &end);
  const int n = std::atoi(parts[2].c_str());
  if (!(a > 0) || !(b >= a) || n < 1 || n > 1000)
    return absl::InvalidArgumentError(
        absl::StrCat("'", text, "': need 0 < FROM <= TO and COUNT in [1, 1000]"));
  std::vector<double> v(n);
  for (int i = 0; i < n; ++i) {
    const double f = n == 1 ? 0 : static_cast<double>(i) / (n - 1);
    v[i] = geometric ? a * std::pow(b / a, f) : a + (b - a) * f;
  }
  return v;
}

absl::StatusOr<std::vector<double>> ParseGenes(const std::string& text, size_t count) {
  std::vector<double> g;
  for (const auto& p : absl::StrSplit(text, absl::ByAnyChar(", "), absl::SkipEmpty())) {
    char* end;
    const std::string s(p);
    const double x = std::strtod(s.c_str(), &end);
    if (*end || !std::isfinite(x))
      return absl::InvalidArgumentError(absl::StrCat("--genes: '", s, "' is not a number"));
    g.push_back(x);
  }
  if (g.size() != count)
    return absl::InvalidArgumentError(absl::StrCat(
        "--genes: expected ", count, " numbers",
        count == 13 ? " (a_T1..a_B3, d_T1..d_B3, T)" : " (the robot's controller's genes)",
        ", got ", g.size()));
  return g;
}

}  // namespace gaitforge::simtool
