// "robot.tracking" (generic_tracking_objective.h).
#include "workers/models/generic/generic_tracking_objective.h"

#include <map>
#include <memory>
#include <mutex>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "robots/registry.h"
#include "workers/models/generic/generic_tracking.h"
#include "workers/objectives/overrides.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::generic {
namespace {

std::string Option(const objectives::EvalInput& in, const char* name, const char* fallback) {
  auto it = in.options.find(name);
  return it == in.options.end() || it->second.empty() ? fallback : it->second;
}

// The descriptor's values with the overrides of option `name` applied.
absl::StatusOr<ParamValues> Overridden(const robots::RobotDescriptor& d,
                                       const objectives::EvalInput& in, const char* name) {
  ParamValues v(d);
  auto set = objectives::ParseOverrides(Option(in, name, ""));
  if (!set.ok()) return absl::InvalidArgumentError(absl::StrCat("option ", name, ": ", set.status().message()));
  for (const auto& [n, value] : *set)
    if (auto s = v.Set(n, value); !s.ok())
      return absl::InvalidArgumentError(absl::StrCat("option ", name, ": ", s.message()));
  return v;
}

// Feed-forwards learned in this worker, by robot, model overrides, iterations and path: the
// same inputs always learn the same forces, so each is learned once.
absl::StatusOr<std::shared_ptr<const FeedForward>> CachedFeedForward(
    const robots::RobotDescriptor& d, const ParamValues& model, const objectives::EvalInput& in,
    const Path& path, const recording::Recording& rec, int iterations) {
  static std::mutex mu;
  static std::map<std::string, std::shared_ptr<const FeedForward>> cache;
  const std::string key = absl::StrFormat(
      "%s|%s|%s|%d|%zu|%.17g|%.17g|%.17g", d.name, in.robot_descriptor, Option(in, "model_set", ""),
      iterations, rec.t.size(), rec.t.back(), path.axes.front().front(), path.axes.front().back());
  {
    std::lock_guard<std::mutex> lock(mu);
    if (auto it = cache.find(key); it != cache.end()) return it->second;
  }
  auto ff = LearnFeedForward(d, model, path, iterations, {});
  if (!ff.ok()) return ff.status();
  auto shared = std::make_shared<const FeedForward>(*std::move(ff));
  std::lock_guard<std::mutex> lock(mu);
  if (cache.size() > 64) cache.clear();
  cache.emplace(key, shared);
  return shared;
}

}  // namespace

objectives::EvalResult RobotTrackingObjective::Evaluate(const objectives::EvalInput& in) const {
  sim::InitThread();
  objectives::EvalResult r;
  auto robot = robots::ResolveRobot(in.robot, in.robot_descriptor);
  if (!robot.ok()) {
    r.reason = "robot: " + std::string(robot.status().message());
    return r;
  }
  const robots::RobotDescriptor& d = **robot;
  auto plant = Overridden(d, in, "set");
  auto model = Overridden(d, in, "model_set");
  if (!plant.ok() || !model.ok()) {
    r.reason = std::string((plant.ok() ? model.status() : plant.status()).message());
    return r;
  }
  for (size_t i = 0; i < in.genes.size() && i < in.gene_names.size(); ++i)
    if (auto s = plant->Set(in.gene_names[i], in.genes[i]); !s.ok()) {
      r.reason = absl::StrCat("gene ", i, ": ", s.message());
      return r;
    }
  double iterations = 20;
  if (!objectives::ParamInRange(in, "ff_iterations", 1, 200, 20, true, iterations, r.reason)) return r;
  const std::string feedforward = Option(in, "feedforward", "none"), fitness = Option(in, "fitness", "iste");
  double max_e = 0, rms_e = 0, iste = 0, model_rms = 0;
  for (const auto& rec : in.recordings) {
    auto path = PathOf(d, *rec, "a path recording");
    if (!path.ok()) {
      r.reason = std::string(path.status().message());
      return r;
    }
    std::shared_ptr<const FeedForward> ff;
    if (feedforward == "model") {
      auto learned = CachedFeedForward(d, *model, in, *path, *rec, static_cast<int>(iterations));
      if (!learned.ok()) {
        r.reason = std::string(learned.status().message());
        return r;
      }
      ff = *learned;
      model_rms += ff->residual_rms_m / in.recordings.size();
    }
    const TrackingResult run = Track(d, *plant, *path, ff.get(), {});
    if (!run.valid) {
      r.reason = run.reason;
      return r;
    }
    max_e += run.max_error_m / in.recordings.size();
    rms_e += run.rms_error_m / in.recordings.size();
    iste += run.iste / in.recordings.size();
  }
  r.metrics = {{"max_error_m", max_e}, {"rms_error_m", rms_e}, {"iste", iste}};
  if (feedforward == "model") r.metrics["model_rms_error_m"] = model_rms;
  r.fitness = -(fitness == "max" ? max_e : fitness == "rms" ? rms_e : iste);
  r.valid = true;
  return r;
}

}  // namespace gaitforge::generic
