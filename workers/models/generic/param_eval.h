#pragma once
// A descriptor expression's value with a robot's current parameter values (the builder's
// files share it).
#include <array>
#include <string>

#include "robots/descriptor.h"
#include "workers/models/generic/generic_world.h"

namespace gaitforge::generic {

inline double Eval(const robots::Expr& e, const ParamValues& v) {
  return e.Eval([&v](const std::string& n) { return v(n); });
}

inline std::array<double, 3> Eval(const robots::Vec3Expr& e, const ParamValues& v) {
  return {Eval(e[0], v), Eval(e[1], v), Eval(e[2], v)};
}

}  // namespace gaitforge::generic
