#include "workers/objectives/ensemble.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "absl/strings/str_cat.h"
#include "services/core/keyed_rng.h"

namespace gaitforge::objectives {
namespace {

// Shortest text that reads back as the same double.
std::string Exact(double v) {
  std::ostringstream out;
  out.precision(17);
  out << v;
  return out.str();
}

double Mean(const std::vector<double>& values) {
  return std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
}

// The sample standard deviation (0 for one value).
double Sd(const std::vector<double>& values) {
  if (values.size() < 2) return 0;
  const double mean = Mean(values);
  double ss = 0;
  for (double x : values) ss += (x - mean) * (x - mean);
  return std::sqrt(ss / static_cast<double>(values.size() - 1));
}

// 0 .. n-1 in an order drawn from rng.
std::vector<int> Shuffle(int n, core::KeyedRng& rng) {
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  for (int i = n - 1; i > 0; --i) std::swap(order[i], order[rng.UniformInt(0, i)]);
  return order;
}

// The same from stream `key` of `seed`: parameter j's stratified draw uses key j, so the
// given samples' order takes key parameters.size(), one no parameter's draw uses.
std::vector<int> Shuffled(int n, uint64_t seed, size_t key) {
  core::KeyedRng rng(seed, 0, key, core::Purpose::kEnsemble);
  return Shuffle(n, rng);
}

// Metrics averaged over the members, except these, which add up.
bool Summed(const std::string& metric) { return metric == "simulated_s"; }

}  // namespace

std::string EnsembleMember::SetText(const EnsembleSpec& spec) const {
  std::vector<std::string> items;
  if (!numeric.empty()) items.push_back(numeric);
  for (size_t j = 0; j < values.size(); ++j)
    items.push_back(absl::StrCat(spec.parameters[j].name, "=", Exact(values[j])));
  std::string out;
  for (const std::string& item : items) out += (out.empty() ? "" : ",") + item;
  return out;
}

bool ParseStatistic(const std::string& name, Statistic* out) {
  if (name == "mean" || name.empty()) *out = Statistic::kMean;
  else if (name == "quantile") *out = Statistic::kQuantile;
  else if (name == "mean_minus_sd") *out = Statistic::kMeanMinusSd;
  else return false;
  return true;
}

std::vector<EnsembleMember> Members(const EnsembleSpec& spec) {
  const int m = std::max(1, spec.members);
  const std::vector<std::string> numerics =
      spec.numerics.empty() ? std::vector<std::string>{""} : spec.numerics;
  const int v = static_cast<int>(numerics.size()), p = std::max(1, spec.start_phases);
  std::vector<EnsembleMember> members(m);
  for (int i = 0; i < m; ++i) {
    members[i].numeric = numerics[i % v];
    members[i].start_phase = static_cast<double>((i / v) % p) / p;
  }
  if (!spec.samples.empty()) {
    // The given samples in an order drawn from a stream of their own, so that every
    // parameter keeps the value its sample pairs it with.
    const int n = static_cast<int>(spec.samples.size());
    const std::vector<int> order = Shuffled(n, spec.seed, spec.parameters.size());
    for (int i = 0; i < m; ++i) members[i].values = spec.samples[order[i % n]];
    return members;
  }
  // Stratified samples: parameter j's range in m strata, each used once, in an order and
  // at offsets drawn from the parameter's own stream.
  for (size_t j = 0; j < spec.parameters.size(); ++j) {
    core::KeyedRng rng(spec.seed, 0, j, core::Purpose::kEnsemble);
    const std::vector<int> order = Shuffle(m, rng);
    const EnsembleRange& r = spec.parameters[j];
    const double lo = r.log ? std::log(r.lo) : r.lo, hi = r.log ? std::log(r.hi) : r.hi;
    for (int i = 0; i < m; ++i) {
      const double x = lo + (order[i] + rng.Uniform01()) / m * (hi - lo);
      members[i].values.push_back(r.log ? std::clamp(std::exp(x), r.lo, r.hi) : x);
    }
  }
  return members;
}

double Combine(std::vector<double> values, const EnsembleSpec& spec) {
  switch (spec.statistic) {
    case Statistic::kMean:
      return Mean(values);
    case Statistic::kMeanMinusSd:
      return Mean(values) - spec.k * Sd(values);
    case Statistic::kQuantile: {
      std::sort(values.begin(), values.end());
      const double at = spec.quantile * static_cast<double>(values.size() - 1);
      const size_t lo = static_cast<size_t>(std::floor(at));
      const size_t hi = std::min(values.size() - 1, lo + 1);
      return values[lo] + (at - lo) * (values[hi] - values[lo]);
    }
  }
  return Mean(values);
}

EvalResult EvaluateEnsemble(const Objective& objective, const EvalInput& input,
                            const EnsembleSpec& spec) {
  EvalResult out;
  const std::vector<EnsembleMember> members = Members(spec);
  std::vector<double> fitness;
  std::map<std::string, double> sums;
  for (size_t i = 0; i < members.size(); ++i) {
    EvalInput in = input;
    const std::string set = members[i].SetText(spec);
    if (!set.empty()) {
      std::string& own = in.options["set"];
      own = own.empty() ? set : own + "," + set;
    }
    if (members[i].start_phase != 0) in.params["start_phase"] = members[i].start_phase;
    const EvalResult r = EvaluateSafely(objective, in);
    sums["simulated_s"] += r.metrics.count("simulated_s") ? r.metrics.at("simulated_s") : 0.0;
    if (!r.valid) {
      out.metrics["simulated_s"] = sums["simulated_s"];
      out.metrics["robust.invalid_member"] = static_cast<double>(i);
      out.reason = absl::StrCat("ensemble member ", i, " (",
                                set.empty() ? "the model as it is" : set, ", start phase ",
                                members[i].start_phase, "): ", r.reason);
      return out;
    }
    fitness.push_back(r.fitness);
    out.metrics[absl::StrCat("member.", i)] = r.fitness;
    for (const auto& [name, value] : r.metrics)
      if (!Summed(name)) sums[name] += value;
  }
  const double n = static_cast<double>(members.size());
  for (const auto& [name, sum] : sums) out.metrics[name] = Summed(name) ? sum : sum / n;
  out.metrics["robust.mean"] = Mean(fitness);
  out.metrics["robust.sd"] = Sd(fitness);
  out.metrics["robust.min"] = *std::min_element(fitness.begin(), fitness.end());
  out.metrics["robust.max"] = *std::max_element(fitness.begin(), fitness.end());
  out.metrics["robust.members"] = n;
  out.fitness = Combine(fitness, spec);
  out.valid = std::isfinite(out.fitness);
  if (!out.valid) out.reason = "the ensemble's statistic is not finite";
  return out;
}

}  // namespace gaitforge::objectives
