// The gap finder's fits (services/diagnosis/fits.h).
#include "services/diagnosis/fits.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <thread>

#include <unistd.h>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "services/core/objective_catalog.h"
#include "services/core/subprocess.h"
#include "services/recording/recording.h"
#include "robots/numerics.h"
#include "robots/registry.h"
#include "workers/effects/effects.h"

namespace gaitforge::diagnosis {

// Numerically irrelevant variants of the model (robots/numerics.h): a hopping robot's travel
// moves by tens of percent under them (docs/diagnosis.md). Every
// held-out error is the mean over them, and a discovery must win in the paired comparison
// across them.
std::vector<std::string> NumericVariants(const v1::DiagnosisSpec& d) {
  auto robot = RobotOf(d);
  if (!robot.ok()) return {""};
  std::vector<std::string> out = robots::StandardNumerics(**robot);
  const robots::Parameter* h = (*robot)->FindParameter(kTimestepParam);
  if (!d.has_timestep_ms() || h == nullptr || !(h->value > 0)) return out;
  // At the diagnosis's own step the timestep variants keep their ratios to it.
  const std::string prefix = std::string(kTimestepParam) + "=";
  for (std::string& v : out)
    if (v.rfind(prefix, 0) == 0)
      v = absl::StrFormat("%s%.9g", prefix,
                          std::stod(v.substr(prefix.size())) * d.timestep_ms() * 1e-3 / h->value);
  return out;
}

// The timestep (s) a numeric variant sets, NAN for one that sets none.
static double VariantStepS(const std::string& variant) {
  const std::string prefix = std::string(kTimestepParam) + "=";
  if (variant.rfind(prefix, 0) != 0) return NAN;
  return std::strtod(variant.c_str() + prefix.size(), nullptr);
}

int FinestStepVariant(const std::vector<std::string>& variants) {
  int finest = -1;
  double least = 0;
  for (int i = 0; i < static_cast<int>(variants.size()); ++i) {
    const double h = VariantStepS(variants[i]);
    if (h > 0 && (finest < 0 || h < least)) finest = i, least = h;
  }
  return finest;
}

std::string BaseSet(const v1::DiagnosisSpec& d, const std::string& extra_set) {
  if (!d.has_timestep_ms() || extra_set.find(kTimestepParam) != std::string::npos)
    return extra_set;
  const std::string step = absl::StrFormat("%s=%.9g", kTimestepParam, d.timestep_ms() * 1e-3);
  return extra_set.empty() ? step : step + "," + extra_set;
}

absl::StatusOr<std::shared_ptr<const robots::RobotDescriptor>> RobotOf(const v1::DiagnosisSpec& d) {
  return robots::ResolveRobot(d.robot(), d.robot_descriptor());
}

std::string RobotArg(const v1::DiagnosisSpec& d) {
  if (d.robot_descriptor().empty()) {
    const robots::RobotDescriptor* builtin = robots::FindRobot(d.robot());
    return builtin && builtin->model == "generic" ? d.robot() : "";
  }
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("gaitforge-robot-" +
                             recording::ContentHash(d.robot_descriptor(), "").substr(0, 16) +
                             ".yaml"))
                               .string();
  static std::mutex mu;
  std::lock_guard<std::mutex> lock(mu);
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    const std::string tmp = path + "." + std::to_string(::getpid());
    std::ofstream(tmp, std::ios::binary) << d.robot_descriptor();
    std::filesystem::rename(tmp, path, ec);
  }
  return path;
}

namespace {

v1::GeneBound Bound(const std::string& name, double lo, double hi) {
  v1::GeneBound b;
  b.set_name(name);
  b.set_lo(lo);
  b.set_hi(hi);
  return b;
}

}  // namespace

Candidate Make(const v1::DiagnosisSpec& d, const std::vector<std::string>& effect_ids) {
  Candidate c;
  c.effects = effect_ids;
  c.label = effect_ids.empty() ? "baseline" : absl::StrJoin(effect_ids, "+");
  for (const auto& b : d.base_parameters()) {
    c.genes.push_back(b);
    c.mean0.push_back(0.5 * (b.lo() + b.hi()));
    c.gene_effect.emplace_back();
  }
  auto robot = RobotOf(d);  // validated before any candidate is made
  for (const auto& id : effect_ids) {
    std::optional<effects::EffectInfo> e;
    if (robot.ok()) e = effects::FindEffect(id, **robot);
    if (!e) continue;
    for (const auto& p : e->params) {
      c.genes.push_back(Bound(p.name, p.lo, p.hi));
      c.mean0.push_back(p.nominal);
      c.gene_effect.push_back(id);
    }
  }
  if (d.time_offset_range_s() > 0) {
    c.genes.push_back(Bound("nuisance.time_offset_s", -d.time_offset_range_s(),
                            d.time_offset_range_s()));
    c.mean0.push_back(0.0);
    c.gene_effect.emplace_back();
  }
  c.nominal = c.mean0;  // a warm start (pipeline.cc StartFrom) moves mean0, not this
  c.k = static_cast<int>(c.genes.size());
  return c;
}

void StartAt(const Candidate& from, Candidate* c, bool hold) {
  for (size_t i = 0; i < c->genes.size() && i < c->mean0.size(); ++i)
    for (size_t j = 0; j < from.genes.size() && j < from.values.size(); ++j) {
      if (from.genes[j].name() != c->genes[i].name()) continue;
      v1::GeneBound& g = c->genes[i];
      const double v = from.values[j], half = 0.02 * std::max(std::abs(v), 1e-9);
      c->mean0[i] = std::clamp(v, g.lo(), g.hi());
      if (!hold) continue;
      g.set_lo(std::max(g.lo(), v - half));
      g.set_hi(std::min(g.hi(), v + half));
    }
  c->sigma0 = hold ? 0.1 : 0.05;
}

bool StartAtBetter(const Candidate& a, const Candidate& b, Candidate* pair) {
  const Candidate& better = !b.ok || (a.ok && a.train <= b.train) ? a : b;
  if (!better.ok) return false;
  StartAt(better, pair, false);
  pair->sigma0 = 0.1;
  return true;
}

v1::DiagnosisSpec WithStructure(const v1::DiagnosisSpec& d, const Candidate& c) {
  v1::DiagnosisSpec out = d;
  const auto joins = [&](const std::string& id) {
    return std::find(c.effects.begin(), c.effects.end(), id) != c.effects.end();
  };
  for (size_t i = 0; i < c.genes.size() && i < c.gene_effect.size(); ++i)
    if (!c.gene_effect[i].empty() && joins(c.gene_effect[i]))
      *out.add_base_parameters() = c.genes[i];
  out.clear_candidates();
  for (const auto& other : d.candidates())
    if (!joins(other)) out.add_candidates(other);
  return out;
}

std::string CalibrationObjective(const v1::DiagnosisSpec& d) {
  if (d.robot_descriptor().empty())
    for (const auto& o : core::ObjectiveCatalog())
      if (!o.calibrates.empty() && o.calibrates == d.robot()) return o.name;
  auto robot = RobotOf(d);
  if (!robot.ok() || (*robot)->model != "generic") return "";
  for (const auto& o : core::ObjectiveCatalog())
    if (o.calibration && o.uses_robot) return o.name;
  return "";
}

v1::StudySpec StudyFor(const v1::DiagnosisSpec& d, const Candidate& c, int evaluations,
                       const StudyInputs& in) {
  v1::StudySpec s;
  s.set_name(absl::StrCat(d.name(), "-", c.label));
  s.set_seed(d.seed());
  s.set_engine("cmaes");
  s.set_population(8);
  s.set_generations(100000);
  auto* o = s.mutable_objective();
  o->set_name(CalibrationObjective(d));
  if (core::FindObjective(o->name())->uses_robot) {
    o->set_robot(d.robot());
    o->set_robot_descriptor(d.robot_descriptor());
  }
  (*o->mutable_options())["error"] = d.error();
  if (!d.channels().empty()) (*o->mutable_options())["channels"] = d.channels();
  for (const auto& [name, value] : d.params()) (*o->mutable_params())[name] = value;
  if (d.has_timestep_ms()) (*o->mutable_params())["timestep_ms"] = d.timestep_ms();
  if (!in.weights.empty()) (*o->mutable_options())["weights"] = in.weights;
  for (const auto& h : in.train) o->add_recordings(h);
  for (const auto& h : in.held) o->add_held_out(h);
  for (const auto& b : c.genes) *s.add_bounds() = b;
  auto* cm = s.mutable_cmaes();
  for (double m : c.mean0) cm->add_mean0(m);
  cm->set_sigma0(c.sigma0);
  cm->set_restarts("none");
  cm->set_max_evaluations(evaluations);
  return s;
}

std::string SetArg(const Candidate& c) {
  std::vector<std::string> parts;
  for (size_t i = 0; i < c.genes.size() && i < c.values.size(); ++i)
    parts.push_back(absl::StrFormat("%s=%.17g", c.genes[i].name(), c.values[i]));
  return absl::StrJoin(parts, ",");
}

// Error of calibration-eval on each of the files with the candidate's fit; empty on failure.
std::vector<double> FileErrors(const Candidate& c, const std::vector<std::string>& files,
                               const v1::DiagnosisSpec& d, const std::string& out_dir,
                               const std::string& extra_set) {
  std::vector<std::string> argv = {
      core::SiblingBinary("gaitforge-sim"), "calibration-eval", "--recordings",
      absl::StrJoin(files, ","), "--options",
      "error=" + d.error() + (d.channels().empty() ? "" : ";channels=" + d.channels())};
  if (!d.params().empty()) {
    std::vector<std::string> params;
    for (const auto& [name, value] : d.params()) params.push_back(absl::StrFormat("%s=%.17g", name, value));
    std::sort(params.begin(), params.end());  // a map's order is not fixed
    argv.insert(argv.end(), {"--objective-params", absl::StrJoin(params, ",")});
  }
  if (const std::string robot = RobotArg(d); !robot.empty())
    argv.insert(argv.end(), {"--robot", robot});
  std::string set = SetArg(c);
  if (const std::string more = BaseSet(d, extra_set); !more.empty())
    set += (set.empty() ? "" : ",") + more;
  if (!set.empty()) argv.insert(argv.end(), {"--set", set});
  if (!out_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(out_dir, ec);
    argv.insert(argv.end(), {"--out-dir", out_dir});
  }
  std::string out;
  if (core::RunCapture(argv, &out) != 0) return {};
  std::vector<double> errors;
  for (size_t at = out.find("\"error\": "); at != std::string::npos;
       at = out.find("\"error\": ", at + 1))
    errors.push_back(std::strtod(out.c_str() + at + 9, nullptr));
  if (!out_dir.empty()) std::ofstream(out_dir + "/eval.json") << out;
  return errors;
}

// Their mean; NAN on failure.
double HeldOutError(const Candidate& c, const std::vector<std::string>& files,
                    const v1::DiagnosisSpec& d, const std::string& out_dir,
                    const std::string& extra_set) {
  const std::vector<double> errors = FileErrors(c, files, d, out_dir, extra_set);
  double sum = 0;
  for (double e : errors) sum += e;
  return errors.empty() ? NAN : sum / errors.size();
}

std::string VariantDir(const std::string& prefix, size_t i) {
  return i == 0 ? prefix : prefix + "-variant-" + std::to_string(i);
}

std::vector<double> VariantErrors(const Candidate& c, const std::vector<std::string>& files,
                                  const v1::DiagnosisSpec& d, const std::string& prefix) {
  const auto variants = NumericVariants(d);
  std::vector<double> errors(variants.size(), NAN);
  TwoAtATime(variants.size(), [&](size_t i) {
    errors[i] = HeldOutError(c, files, d, prefix.empty() ? "" : VariantDir(prefix, i), variants[i]);
  });
  return errors;
}

// weighting: floor. The spread (sd) of the uncalibrated model's error on each training file
// over the numeric variants, and weights 1 / sd^2 (sd at least a tenth of the median, so a
// file the variants agree on cannot take all the weight), scaled to a mean of 1. Empty when
// an evaluation fails.
std::vector<double> FloorWeights(const v1::DiagnosisSpec& d, const std::vector<std::string>& files,
                                 std::vector<double>* floors, std::vector<double>* variant_means) {
  const auto variants = NumericVariants(d);
  std::vector<std::vector<double>> e(variants.size());
  for (size_t v = 0; v < variants.size(); ++v) {
    e[v] = FileErrors(Make(d, {}), files, d, "", variants[v]);
    if (e[v].size() != files.size()) return {};
  }
  if (variant_means) {
    variant_means->clear();
    for (const auto& ev : e) {
      double sum = 0;
      for (double x : ev) sum += x;
      variant_means->push_back(sum / ev.size());
    }
  }
  floors->assign(files.size(), 0);
  for (size_t f = 0; f < files.size(); ++f) {
    double mean = 0, sq = 0;
    for (const auto& ev : e) mean += ev[f] / e.size();
    for (const auto& ev : e) sq += (ev[f] - mean) * (ev[f] - mean);
    (*floors)[f] = std::sqrt(sq / (e.size() - 1));
  }
  return WeightsFromFloors(*floors, d.weighting() == "pooled");
}

bool FloorsMeasured(const v1::DiagnosisSpec& d) {
  return d.weighting() == "floor" || d.weighting() == "pooled";
}

std::vector<double> WeightsFromFloors(const std::vector<double>& floors, bool pooled) {
  if (floors.empty()) return {};
  std::vector<double> sorted = floors;
  std::sort(sorted.begin(), sorted.end());
  const size_t n = sorted.size();
  const double median = n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
  const double least = 0.1 * sorted[n / 2];
  std::vector<double> w;
  double sum = 0;
  for (double sd : floors) {
    w.push_back(pooled ? 1 / (sd * sd + median * median + 1e-30)
                       : 1 / std::max(sd * sd, least * least + 1e-30));
    sum += w.back();
  }
  for (double& x : w) x *= w.size() / sum;
  return w;
}

std::string NumericsNote(const std::vector<std::string>& variants,
                         const std::vector<double>& training_errors, const DecisionRule& unit) {
  if (variants.empty() || training_errors.size() != variants.size() || !(training_errors[0] > 0))
    return "";
  size_t best = 0;
  for (size_t i = 1; i < variants.size(); ++i)
    if (training_errors[i] < training_errors[best]) best = i;
  if (!(training_errors[best] < kUnconvergedShare * training_errors[0])) return "";
  return absl::StrFormat(
      "the model's numerics are not converged for these recordings: with %s the uncalibrated "
      "model misses the training recordings by %.3g %s instead of %.3g %s (%+.0f%%), so an "
      "effect named here may stand in for the step's own error; diagnose a model whose "
      "numerics converge (gaitforge-bench-engines measures a robot's step)",
      variants[best], unit.error_scale * training_errors[best], unit.error_unit,
      unit.error_scale * training_errors[0], unit.error_unit,
      100 * (training_errors[best] / training_errors[0] - 1));
}

double FinerStepMs(const std::vector<std::string>& variants,
                   const std::vector<double>& training_errors, double own_step_ms) {
  if (variants.size() != training_errors.size() || variants.empty() ||
      !(training_errors[0] > 0))
    return -1;
  double best_ms = -1, best_error = kUnconvergedShare * training_errors[0];
  for (size_t i = 1; i < variants.size(); ++i) {
    const double ms = 1e3 * VariantStepS(variants[i]);
    if (!std::isfinite(ms)) continue;
    if (ms < own_step_ms && training_errors[i] < best_error) {
      best_ms = ms;
      best_error = training_errors[i];
    }
  }
  return best_ms;
}

void TwoAtATime(size_t n, const std::function<void(size_t)>& run) {
  for (size_t i = 0; i < n; i += 2) {
    std::thread t;
    if (i + 1 < n) t = std::thread([&run, i] { run(i + 1); });
    run(i);
    if (t.joinable()) t.join();
  }
}

// Held-out error of c under every numeric variant, two at a time; c.held is their mean (NAN if
// any variant fails: a fit that only works at one timestep is no fit).
void ScoreHeldOut(Candidate& c, const std::vector<std::string>& files, const v1::DiagnosisSpec& d,
                  const std::string& prefix) {
  c.held_variants = VariantErrors(c, files, d, prefix);
  double sum = 0;
  for (double e : c.held_variants) sum += e;
  c.held = sum / c.held_variants.size();
}

}  // namespace gaitforge::diagnosis
