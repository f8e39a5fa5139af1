#pragma once
// What a worker computes for one genotype. Objectives are pure: the result depends only on
// (genes, bounds, params), never on the thread, the order of calls or the time.
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "services/recording/recording.h"

namespace gaitforge::objectives {

struct EvalInput {
  std::vector<double> genes;
  std::vector<double> lo, hi;             // the study's search space
  std::vector<std::string> gene_names;    // the space's gene names (calibration: parameters)
  std::map<std::string, double> params;   // validated against the objective catalog
  std::map<std::string, std::string> options;  // string-valued options (catalog-checked)
  // The robot of a robot-agnostic objective: a built-in's name, or a descriptor's text the
  // study carries (objective.robot, objective.robot_descriptor).
  std::string robot, robot_descriptor;
  // Recordings the objective compares with (fetched and cached by content hash).
  std::vector<std::shared_ptr<const recording::Recording>> recordings;
};

// Fitness is "higher is better". A failed evaluation (diverged simulation, bad genotype)
// has valid = false and a reason; it is a result, not an error.
struct EvalResult {
  bool valid = false;
  double fitness = 0.0;
  std::string reason;
  std::map<std::string, double> metrics;
};

class Objective {
 public:
  virtual ~Objective() = default;
  // Must be safe to call from several threads at once.
  virtual EvalResult Evaluate(const EvalInput& input) const = 0;
};

// Objectives by catalog name (services/core/objective_catalog.h). This is where models
// plug in: each model registers its objectives here.
class ObjectiveRegistry {
 public:
  void Register(const std::string& name, std::shared_ptr<const Objective> objective);
  // nullptr when this worker does not implement `name`.
  const Objective* Find(const std::string& name) const;
  std::vector<std::string> Names() const;

 private:
  std::map<std::string, std::shared_ptr<const Objective>> objectives_;
};

// Every objective built into this worker.
ObjectiveRegistry DefaultRegistry();

// Runs an objective, turning exceptions and non-finite fitness into invalid results.
EvalResult EvaluateSafely(const Objective& objective, const EvalInput& input);

// The numeric param `name` of `input`, `fallback` when absent; false (with the error "param
// NAME = V is outside [LO, HI]") when outside [lo, hi] or, for `integer`, not whole.
bool ParamInRange(const EvalInput& input, const char* name, double lo, double hi, double fallback,
                  bool integer, double& value, std::string& error);

}  // namespace gaitforge::objectives
