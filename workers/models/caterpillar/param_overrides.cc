#include "workers/models/caterpillar/param_overrides.h"

#include <cmath>
#include <functional>
#include <sstream>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"

namespace gaitforge::caterpillar {
namespace {

using P = CaterpillarParams;

// A field SetParam may change: its name, unit, range (caterpillar.yaml) and where it lives.
struct Field {
  const char* name;
  const char* unit;
  double lo, hi;
  std::function<double&(P&)> ref;
};

#define GF_REF(member) [](P& p) -> double& { return p.member; }

const std::vector<Field>& Fields() {
  static const std::vector<Field> fields = {
      {"actuators.force_n", "N", 0, 100, GF_REF(actuators.force_n)},
      {"actuators.return_spring_n_per_m", "N/m", 0, 1e4, GF_REF(actuators.return_spring_n_per_m)},
      {"actuators.max_length_m", "m", 0.001, 1, GF_REF(actuators.max_length_m)},
      {"links.flexure.axial_stiffness_n_per_m", "N/m", 1, 1e6, GF_REF(links.flexure.axial_n_per_m)},
      {"links.flexure.bending_stiffness_nm_per_rad", "N m/rad", 1e-4, 100,
       GF_REF(links.flexure.bending_nm_per_rad)},
      {"links.segment.axial_stiffness_n_per_m", "N/m", 1, 1e6, GF_REF(links.segment.axial_n_per_m)},
      {"links.segment.bending_stiffness_nm_per_rad", "N m/rad", 1e-4, 100,
       GF_REF(links.segment.bending_nm_per_rad)},
      {"links.axial_damping_ratio", "of critical", 0.01, 10, GF_REF(links.axial_damping_ratio)},
      {"links.bending_damping_ratio", "of critical", 0.01, 10, GF_REF(links.bending_damping_ratio)},
      {"lumps.mass_kg", "kg", 0.001, 1, GF_REF(lumps.mass_kg)},
      {"ground.contact_erp", "", 0.01, 1, GF_REF(ground.contact_erp)},
      {"ground.contact_cfm", "m/(N s)", 0, 1e-2, GF_REF(ground.contact_cfm)},
      {"ground.friction_coefficient", "", 0, 10, GF_REF(ground.friction_coefficient)},
      // The model's resolution in time (a reference rig may step finer than the model).
      {"simulation.timestep_s", "s", 5e-5, 2e-3, GF_REF(simulation.timestep_s)},
      // Candidate effects (CaterpillarParams::Effects; 0 = off).
      {"effect.tether_force_n", "N", 0, 20, GF_REF(effects.tether_force_n)},
      {"effect.tether_stiffness_n_per_m", "N/m", 0, 1000, GF_REF(effects.tether_stiffness_n_per_m)},
      {"effect.slope_rad", "rad", -0.3, 0.3, GF_REF(effects.slope_rad)},
      {"effect.drag_n_s_per_m", "N s/m", 0, 10, GF_REF(effects.drag_n_s_per_m)},
      {"effect.friction_forward", "", 0, 10, GF_REF(effects.friction_forward)},
      {"effect.friction_backward", "", 0, 10, GF_REF(effects.friction_backward)},
      {"effect.actuator_lag_s", "s", 0, 1, GF_REF(effects.actuator_lag_s)},
      {"effect.actuator_delay_s", "s", 0, 0.2, GF_REF(effects.actuator_delay_s)},
      {"effect.actuator_deadband_n", "N", 0, 20, GF_REF(effects.actuator_deadband_n)},
      {"effect.spring_softening", "1/m", 0, 1000, GF_REF(effects.spring_softening)},
      {"effect.lump_compliance_per_mpa", "1/MPa", 0, 100, GF_REF(effects.lump_compliance_per_mpa)},
  };
  return fields;
}
#undef GF_REF

// Scale names and the absolute fields each multiplies.
struct Scale {
  const char* name;
  std::vector<const char*> fields;
};

const std::vector<Scale>& Scales() {
  static const std::vector<Scale> scales = {
      {"scale.link_stiffness",
       {"links.flexure.axial_stiffness_n_per_m", "links.flexure.bending_stiffness_nm_per_rad",
        "links.segment.axial_stiffness_n_per_m", "links.segment.bending_stiffness_nm_per_rad"}},
      {"scale.axial_stiffness",
       {"links.flexure.axial_stiffness_n_per_m", "links.segment.axial_stiffness_n_per_m"}},
      {"scale.bending_stiffness",
       {"links.flexure.bending_stiffness_nm_per_rad",
        "links.segment.bending_stiffness_nm_per_rad"}},
      {"scale.mass", {"lumps.mass_kg"}},
      {"scale.link_damping", {"links.axial_damping_ratio", "links.bending_damping_ratio"}},
  };
  return scales;
}

const Field* FindField(std::string_view name) {
  for (const Field& f : Fields()) {
    if (name == f.name) return &f;
  }
  return nullptr;
}

std::string Num(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

std::string Range(const Field& f) {
  return absl::StrCat("[", Num(f.lo), ", ", Num(f.hi), "]", *f.unit ? " " : "", f.unit);
}

absl::Status CheckField(const Field& f, double v) {
  if (!std::isfinite(v) || v < f.lo || v > f.hi) {
    return absl::InvalidArgumentError(
        absl::StrCat(f.name, " = ", Num(v), *f.unit ? " " : "", f.unit, " is outside ", Range(f)));
  }
  return absl::OkStatus();
}

}  // namespace

const std::vector<std::string>& CalibratableParamNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const Field& f : Fields()) n.push_back(f.name);
    for (const Scale& s : Scales()) n.push_back(s.name);
    return n;
  }();
  return names;
}

const std::vector<std::string>& NuisanceParamNames() {
  static const std::vector<std::string> names = {kTimeOffsetParam};
  return names;
}

bool IsNuisanceParam(std::string_view name) {
  for (const auto& n : NuisanceParamNames()) {
    if (name == n) return true;
  }
  return false;
}

absl::Status ValidateCalibratableFields(const CaterpillarParams& params) {
  P p = params;  // Field::ref needs a mutable object; nothing is written
  for (const Field& f : Fields()) {
    if (absl::Status s = CheckField(f, f.ref(p)); !s.ok()) return s;
  }
  const auto& a = params.actuators;
  if (!(a.max_length_m > a.min_length_m)) {
    return absl::InvalidArgumentError(
        absl::StrCat("actuators.max_length_m = ", Num(a.max_length_m),
                     " m must exceed actuators.min_length_m = ", Num(a.min_length_m), " m"));
  }
  const double rest = params.RestActuatorLength();
  if (rest > a.max_length_m + 1e-9) {
    return absl::InvalidArgumentError(absl::StrCat("actuators.max_length_m = ", Num(a.max_length_m),
                                                   " m is below the rest actuator length ",
                                                   Num(rest), " m"));
  }
  return absl::OkStatus();
}

absl::Status SetParam(CaterpillarParams& params, std::string_view name_view, double value) {
  const std::string name(name_view);
  if (IsNuisanceParam(name)) {
    return absl::InvalidArgumentError(
        absl::StrCat(name,
                     " is a nuisance parameter of the comparison, handled by the calibration "
                     "objective, not a model parameter"));
  }
  P p = params;
  if (const Field* f = FindField(name)) {
    if (absl::Status s = CheckField(*f, value); !s.ok()) return s;
    f->ref(p) = value;
    if (name == std::string_view("ground.friction_coefficient")) {
      p.ground.infinite_friction = false;
    }
  } else {
    const Scale* scale = nullptr;
    for (const Scale& s : Scales()) {
      if (name == s.name) scale = &s;
    }
    if (scale == nullptr) {
      return absl::InvalidArgumentError(
          absl::StrCat("unknown caterpillar calibration parameter '", name,
                       "'; known: ", absl::StrJoin(CalibratableParamNames(), ", "),
                       "; nuisance: ", absl::StrJoin(NuisanceParamNames(), ", ")));
    }
    if (!std::isfinite(value) || !(value > 0)) {
      return absl::InvalidArgumentError(
          absl::StrCat(name, " = ", Num(value), " must be a positive finite factor"));
    }
    for (const char* field : scale->fields) {
      const Field& f = *FindField(field);
      double& v = f.ref(p);
      v *= value;
      if (absl::Status s = CheckField(f, v); !s.ok()) {
        return absl::InvalidArgumentError(
            absl::StrCat(name, " = ", Num(value), " makes ", s.message()));
      }
    }
  }
  if (absl::Status s = ValidateCalibratableFields(p); !s.ok()) {
    return absl::InvalidArgumentError(
        absl::StrCat("after ", name, " = ", Num(value), ": ", s.message()));
  }
  params = p;
  return absl::OkStatus();
}

}  // namespace gaitforge::caterpillar
