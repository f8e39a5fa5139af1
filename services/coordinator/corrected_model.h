#pragma once
// What a gait study takes from a fitted model (a diagnosis's or a calibration's): its values
// in front of the spec's own `set`, and with objective.robust its fitted ranges as ensemble
// parameters (docs/objectives.md, "From a diagnosis", "From a calibration").
#include <string>

#include "gaitforge/v1/common.pb.h"

namespace gaitforge::coordinator {

// objective.options.set becomes `corrected` followed by the spec's own items (which win).
void PrependSet(v1::ObjectiveSpec* objective, const std::string& corrected);

// Whether objective.robust.parameters lists `name`.
bool ListsRange(const v1::ObjectiveSpec& objective, const std::string& name);

// Adds {name, lo, hi} to objective.robust.parameters unless the spec already lists name.
void AddEnsembleRange(v1::ObjectiveSpec* objective, const std::string& name, double lo, double hi);

}  // namespace gaitforge::coordinator
