#include "services/coordinator/corrected_model.h"

#include <algorithm>

namespace gaitforge::coordinator {

void PrependSet(v1::ObjectiveSpec* objective, const std::string& corrected) {
  std::string& own = (*objective->mutable_options())["set"];
  own = own.empty() ? corrected : corrected.empty() ? own : corrected + "," + own;
  if (own.empty()) objective->mutable_options()->erase("set");
}

bool ListsRange(const v1::ObjectiveSpec& objective, const std::string& name) {
  const auto& listed = objective.robust().parameters();
  return std::any_of(listed.begin(), listed.end(), [&](const auto& p) { return p.name() == name; });
}

void AddEnsembleRange(v1::ObjectiveSpec* objective, const std::string& name, double lo, double hi) {
  if (ListsRange(*objective, name)) return;
  auto* p = objective->mutable_robust()->add_parameters();
  p->set_name(name);
  p->set_lo(lo);
  p->set_hi(hi);
}

}  // namespace gaitforge::coordinator
