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
  // The ranges the descriptor must give (controller.<key>: [lo, hi]).
  std::vector<std::string> range_keys;
  // The gene space of a controller of this kind (its actuators and ranges already read).
  std::vector<Gene> (*genes)(const Controller&);
  // The gait period (s) of a genotype of this kind.
  double (*period_s)(const std::vector<double>& genes);
  // Each of the controller's actuators' command at time t >= 0 (s), in its `actuators`
  // order: phase_onoff 1 (ON) or 0 (OFF); sine the set-point angle (rad). The genes must
  // be a genotype of this kind (the gene space's count).
  std::vector<double> (*commands)(const Controller& c, const std::vector<double>& genes,
                                  double t);
  // True when the commands are set-point angles (servos), false for on/off.
  bool set_points = true;
};

const std::vector<ControllerKind>& ControllerKinds();
const ControllerKind* FindControllerKind(std::string_view name);  // nullptr when unknown
std::vector<std::string> ControllerKindNames();

}  // namespace gaitforge::robots
