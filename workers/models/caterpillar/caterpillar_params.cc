#include "workers/models/caterpillar/caterpillar_params.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "robots/descriptor_parser.h"
#include "robots/registry.h"

namespace gaitforge::caterpillar {
namespace {

using P = CaterpillarParams;

// Which field of CaterpillarParams each descriptor parameter is. Ranges, units and nominal
// values are the descriptor's (robots/caterpillar/robot.yaml), not written here.
struct FieldRef {
  const char* name;
  double (*get)(const P&);
  void (*set)(P&, double);
};

#define GF_FIELD(name, member) \
  FieldRef { name, [](const P& p) { return static_cast<double>(p.member); }, \
             [](P& p, double v) { p.member = static_cast<decltype(p.member)>(v); } }

const std::vector<FieldRef>& Fields() {
  static const std::vector<FieldRef> fields = {
      GF_FIELD("lumps.mass_kg", lumps.mass_kg),
      GF_FIELD("lumps.size_x_m", lumps.size_x_m),
      GF_FIELD("lumps.size_y_m", lumps.size_y_m),
      GF_FIELD("lumps.size_z_m", lumps.size_z_m),
      GF_FIELD("lumps.spacing_m", lumps.spacing_m),
      GF_FIELD("links.flexure.axial_stiffness_n_per_m", links.flexure.axial_n_per_m),
      GF_FIELD("links.flexure.bending_stiffness_nm_per_rad", links.flexure.bending_nm_per_rad),
      GF_FIELD("links.segment.axial_stiffness_n_per_m", links.segment.axial_n_per_m),
      GF_FIELD("links.segment.bending_stiffness_nm_per_rad", links.segment.bending_nm_per_rad),
      GF_FIELD("links.axial_damping_ratio", links.axial_damping_ratio),
      GF_FIELD("links.bending_damping_ratio", links.bending_damping_ratio),
      GF_FIELD("actuators.force_n", actuators.force_n),
      GF_FIELD("actuators.return_spring_n_per_m", actuators.return_spring_n_per_m),
      GF_FIELD("actuators.min_length_m", actuators.min_length_m),
      GF_FIELD("actuators.max_length_m", actuators.max_length_m),
      GF_FIELD("actuators.rear_attach_x_m", actuators.rear_attach_x_m),
      GF_FIELD("actuators.front_attach_x_m", actuators.front_attach_x_m),
      GF_FIELD("actuators.top_attach_z_m", actuators.top_attach_z_m),
      GF_FIELD("actuators.bottom_attach_z_m", actuators.bottom_attach_z_m),
      GF_FIELD("actuators.stop_erp", actuators.stop_erp),
      GF_FIELD("actuators.stop_cfm", actuators.stop_cfm),
      GF_FIELD("actuators.overrun_tolerance_m", actuators.overrun_tolerance_m),
      // Infinite: the no-slip ground; a finite value makes the ground Coulomb.
      FieldRef{"ground.friction_coefficient",
               [](const P& p) {
                 return p.ground.infinite_friction ? INFINITY : p.ground.friction_coefficient;
               },
               [](P& p, double v) {
                 p.ground.infinite_friction = std::isinf(v);
                 p.ground.friction_coefficient = std::isinf(v) ? 0 : v;
               }},
      GF_FIELD("ground.contact_erp", ground.contact_erp),
      GF_FIELD("ground.contact_cfm", ground.contact_cfm),
      GF_FIELD("markers.offset_x_m", markers.offset_x_m),
      GF_FIELD("markers.offset_z_m", markers.offset_z_m),
      GF_FIELD("simulation.gravity_m_per_s2", simulation.gravity_m_per_s2),
      GF_FIELD("simulation.timestep_s", simulation.timestep_s),
      GF_FIELD("simulation.settle_cycles", simulation.settle_cycles),
      GF_FIELD("simulation.measured_cycles", simulation.measured_cycles),
      GF_FIELD("simulation.solver_erp", simulation.solver_erp),
      GF_FIELD("simulation.solver_cfm", simulation.solver_cfm),
      GF_FIELD("simulation.max_speed_m_per_s", simulation.max_speed_m_per_s),
      GF_FIELD("simulation.max_excursion_m", simulation.max_excursion_m),
      GF_FIELD("effect.tether_force_n", effects.tether_force_n),
      GF_FIELD("effect.tether_stiffness_n_per_m", effects.tether_stiffness_n_per_m),
      GF_FIELD("effect.slope_rad", effects.slope_rad),
      GF_FIELD("effect.drag_n_s_per_m", effects.drag_n_s_per_m),
      GF_FIELD("effect.friction_forward", effects.friction_forward),
      GF_FIELD("effect.friction_backward", effects.friction_backward),
      GF_FIELD("effect.actuator_lag_s", effects.actuator_lag_s),
      GF_FIELD("effect.actuator_delay_s", effects.actuator_delay_s),
      GF_FIELD("effect.actuator_deadband_n", effects.actuator_deadband_n),
      GF_FIELD("effect.spring_softening", effects.spring_softening),
      GF_FIELD("effect.lump_compliance_per_mpa", effects.lump_compliance_per_mpa),
  };
  return fields;
}
#undef GF_FIELD

const FieldRef* FindField(std::string_view name) {
  for (const FieldRef& f : Fields())
    if (name == f.name) return &f;
  return nullptr;
}

}  // namespace

absl::StatusOr<double> GetField(const CaterpillarParams& p, std::string_view name) {
  const FieldRef* f = FindField(name);
  if (f == nullptr)
    return absl::NotFoundError(absl::StrCat("the caterpillar model has no parameter ", std::string(name)));
  return f->get(p);
}

absl::Status SetField(CaterpillarParams& p, std::string_view name, double value) {
  const FieldRef* f = FindField(name);
  if (f == nullptr)
    return absl::NotFoundError(absl::StrCat("the caterpillar model has no parameter ", std::string(name)));
  f->set(p, value);
  return absl::OkStatus();
}

absl::StatusOr<CaterpillarParams> CaterpillarParamsFrom(const robots::RobotDescriptor& d) {
  // The dedicated model reads the caterpillar's parameters; the generic builder builds it.
  if (d.name != "caterpillar") {
    return absl::InvalidArgumentError(
        absl::StrCat(d.source, ": robot '", d.name, "' is not the caterpillar"));
  }
  CaterpillarParams p;
  for (const robots::Parameter& param : d.parameters) {
    const FieldRef* f = FindField(param.name);
    if (f == nullptr) {
      return absl::InvalidArgumentError(
          absl::StrCat(param.mark.ToString(), ": ", param.name,
                       ": the caterpillar model has no such parameter"));
    }
    f->set(p, param.value);
  }
  for (const FieldRef& f : Fields()) {
    if (d.FindParameter(f.name) != nullptr) continue;
    return absl::InvalidArgumentError(
        absl::StrCat(d.source, ": missing parameter ", f.name, " (the caterpillar model needs it)"));
  }
  return p;
}

absl::StatusOr<CaterpillarParams> ParseCaterpillarParams(const std::string& text,
                                                         const std::string& source) {
  auto d = robots::ParseDescriptor(text, source);
  if (!d.ok()) return d.status();
  return CaterpillarParamsFrom(*d);
}

absl::StatusOr<CaterpillarParams> LoadCaterpillarParams(const std::string& path) {
  auto d = robots::LoadDescriptor(path);
  if (!d.ok()) return d.status();
  return CaterpillarParamsFrom(*d);
}

const robots::RobotDescriptor& CaterpillarDescriptor() { return robots::Robot("caterpillar"); }

const CaterpillarParams& DefaultCaterpillarParams() {
  static const CaterpillarParams params = [] {
    auto p = CaterpillarParamsFrom(CaterpillarDescriptor());
    if (!p.ok()) throw std::runtime_error(std::string(p.status().message()));
    return *p;
  }();
  return params;
}

}  // namespace gaitforge::caterpillar
