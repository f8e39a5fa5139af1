#include "workers/objectives/objective.h"

#include <cmath>
#include <exception>

#include "absl/strings/str_cat.h"
#include "workers/objectives/analytic.h"

namespace gaitforge::objectives {

void ObjectiveRegistry::Register(const std::string& name,
                                 std::shared_ptr<const Objective> objective) {
  objectives_[name] = std::move(objective);
}

const Objective* ObjectiveRegistry::Find(const std::string& name) const {
  auto it = objectives_.find(name);
  return it == objectives_.end() ? nullptr : it->second.get();
}

std::vector<std::string> ObjectiveRegistry::Names() const {
  std::vector<std::string> out;
  for (const auto& [name, o] : objectives_) out.push_back(name);
  return out;
}

ObjectiveRegistry DefaultRegistry() {
  ObjectiveRegistry r;
  RegisterAnalytic(r);
  return r;
}

EvalResult EvaluateSafely(const Objective& objective, const EvalInput& input) {
  EvalResult r;
  try {
    r = objective.Evaluate(input);
  } catch (const std::exception& e) {
    r = EvalResult{};
    r.reason = std::string("evaluation failed: ") + e.what();
    return r;
  } catch (...) {
    r = EvalResult{};
    r.reason = "evaluation failed: unknown exception";
    return r;
  }
  if (r.valid && !std::isfinite(r.fitness)) {
    r.valid = false;
    r.reason = "non-finite fitness";
  }
  if (!r.valid) r.fitness = 0.0;
  for (auto it = r.metrics.begin(); it != r.metrics.end();) {
    it = std::isfinite(it->second) ? std::next(it) : r.metrics.erase(it);
  }
  return r;
}

bool ParamInRange(const EvalInput& in, const char* name, double lo, double hi, double fallback,
                  bool integer, double& value, std::string& error) {
  auto it = in.params.find(name);
  value = it == in.params.end() ? fallback : it->second;
  if (!(value >= lo && value <= hi) || (integer && value != std::floor(value))) {
    error = absl::StrCat("param ", name, " = ", value, " is outside [", lo, ", ", hi, "]",
                         integer ? " (a whole number)" : "");
    return false;
  }
  return true;
}

}  // namespace gaitforge::objectives
