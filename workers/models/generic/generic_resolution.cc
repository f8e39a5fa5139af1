// GenericWorld's bodies and their resolution (generic_world.h): a body is one ODE body, or,
// under effect.lump_compliance_per_mpa, two halves joined by the material between them.
#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "workers/models/generic/generic_world.h"
#include "workers/models/generic/param_eval.h"

namespace gaitforge::generic {
namespace {

// Largest h*omega of a half-body block; past it the block is too stiff for the timestep
// and the body stays rigid.
constexpr double kMaxInnerStepOmega = 2.5;

}  // namespace

int GenericWorld::BodyIndex(const std::string& name) const {
  for (size_t i = 0; i < d_.bodies.size(); ++i)
    if (d_.bodies[i].name == name) return static_cast<int>(i);
  return -1;
}

// The block between a split body's half centres (length l = half its x length, its y-z
// section): axial E A / l, bending E I / l about y; damped like the first spring link that
// joins the body.
GenericWorld::Split GenericWorld::SplitOf(int body, const std::array<double, 3>& size,
                                          double mass, const ParamValues& v) const {
  Split s;
  if (!(fx_.lump_compliance > 0)) return s;
  const robots::Joint* link = nullptr;
  for (const robots::Joint& j : d_.joints)
    if (j.type == "spring_link" && !link &&
        (j.body1 == d_.bodies[body].name || j.body2 == d_.bodies[body].name))
      link = &j;
  if (!link) return s;
  const double modulus = 1e6 / fx_.lump_compliance;
  const double l = size[0] / 2;
  const double area = size[1] * size[2];
  const double second_moment = size[1] * size[2] * size[2] * size[2] / 12;
  s.k = modulus * area / l;
  s.kappa = modulus * second_moment / l;
  dMass half;
  dMassSetBoxTotal(&half, mass / 2, size[0] / 2, size[1], size[2]);
  const double omega = std::max(std::sqrt(s.k / (mass / 4)), std::sqrt(s.kappa / (half.I[1 * 4 + 1] / 2)));
  s.on = h_ * omega <= kMaxInnerStepOmega;
  s.zeta = Eval(*link->axial_damping_ratio, v);
  s.zeta_bend = Eval(*link->damping_ratio, v);
  return s;
}

absl::Status GenericWorld::BuildBody(int index, const ParamValues& v) {
  const robots::Body& b = d_.bodies[index];
  const auto size = Eval(b.size, v);
  const auto pos = Eval(b.position, v);
  const double m = Eval(b.mass, v);
  if (!(size[0] > 0 && size[1] > 0 && size[2] > 0 && m > 0))
    return absl::InvalidArgumentError(absl::StrCat(
        b.mark.ToString(), ": body ", b.name, " needs a positive size and mass, got size [",
        size[0], ", ", size[1], ", ", size[2], "] m and mass ", m, " kg"));
  dMatrix3 rot;
  Built built;
  built.first = static_cast<int>(bodies_.size());
  built.centre = pos;
  dMass whole;
  if (b.shape == "sphere")
    dMassSetSphereTotal(&whole, m, size[0] / 2);
  else
    dMassSetBoxTotal(&whole, m, size[0], size[1], size[2]);
  built.mass = m;
  built.inertia_y = whole.I[1 * 4 + 1];
  if (b.pitch) {
    const double pitch = Eval(*b.pitch, v);
    dRFromAxisAndAngle(rot, 0, 1, 0, pitch);
    built.axis = {rot[0], rot[4], rot[8]};  // the body's x axis in the world
  }
  const Split split = SplitOf(index, size, m, v);
  splits_.push_back(split);
  if (!split.on) {
    CreateBody(b.name, size, m, pos, b.pitch ? rot : nullptr, b.shape == "sphere");
    built_.push_back(built);
    return absl::OkStatus();
  }
  built.parts = 2;
  built.half_x = size[0] / 2 / 2;
  const std::array<double, 3> half_size = {size[0] / 2, size[1], size[2]};
  for (int part = 0; part < 2; ++part) {
    const double offset = part == 0 ? -built.half_x : built.half_x;
    std::array<double, 3> at;
    for (int k = 0; k < 3; ++k) at[k] = pos[k] + offset * built.axis[k];
    CreateBody(b.name + (part == 0 ? " (rear half)" : " (front half)"), half_size, m / 2, at,
               b.pitch ? rot : nullptr);
  }
  built_.push_back(built);
  return absl::OkStatus();
}

int GenericWorld::NearPart(int body, const std::array<double, 3>& world) const {
  const Built& b = built_[body];
  if (b.parts == 1) return b.first;
  double along = 0;
  for (int k = 0; k < 3; ++k) along += (world[k] - b.centre[k]) * b.axis[k];
  return along > 0 ? b.first + 1 : b.first;
}

std::pair<int, std::array<double, 3>> GenericWorld::Locate(int body,
                                                           std::array<double, 3> point) const {
  const Built& b = built_[body];
  if (b.parts == 1) return {b.first, point};
  if (point[0] <= 0) {
    point[0] += b.half_x;
    return {b.first, point};
  }
  point[0] -= b.half_x;
  return {b.first + 1, point};
}

}  // namespace gaitforge::generic
