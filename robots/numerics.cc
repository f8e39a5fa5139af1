#include "robots/numerics.h"

namespace gaitforge::robots {

std::vector<std::string> StandardNumerics(const RobotDescriptor& d) {
  static const std::vector<std::string> all = {
      "", "simulation.timestep_s=0.0005", "simulation.timestep_s=0.00075",
      "simulation.timestep_s=0.00125", "ground.contact_cfm=3e-6", "ground.contact_cfm=3e-5"};
  std::vector<std::string> out;
  for (const std::string& s : all)
    if (s.empty() || d.FindParameter(s.substr(0, s.find('='))) != nullptr) out.push_back(s);
  return out;
}

}  // namespace gaitforge::robots
