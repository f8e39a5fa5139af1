#pragma once
// Controller kinds a descriptor may name (docs/robots.md, "controller"). A kind turns the
// descriptor's controller section into its gene space; the worker side that runs it is
// registered by the same name. Adding a kind is one entry in ControllerKinds().
#include <string>
#include <string_view>
#include <vector>

#include "robots/descriptor.h"

namespace gaitforge::robots {

struct ControllerKind {
  std::string name;
  std::string doc;
  // The gene space of a controller of this kind (its actuators and period already read).
  std::vector<Gene> (*genes)(const Controller&);
};

const std::vector<ControllerKind>& ControllerKinds();
const ControllerKind* FindControllerKind(std::string_view name);  // nullptr when unknown
std::vector<std::string> ControllerKindNames();

}  // namespace gaitforge::robots
