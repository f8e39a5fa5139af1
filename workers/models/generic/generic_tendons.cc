// GenericWorld's tendons (generic_world.h; robots/descriptor.h, Actuator "tendon"): a rod
// fixed to a distal body and pulled from a proximal one, as paper 004's continuum arm is
// driven. The rod's tension is carried by the backbone between them, so its net effect is
// a moment: r x f on the distal body and the opposite on the proximal one (or the world).
#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "workers/models/generic/generic_world.h"
#include "workers/models/generic/param_eval.h"

namespace gaitforge::generic {

absl::Status GenericWorld::BuildTendon(const robots::Actuator& a, int index, const ParamValues& v) {
  Tendon t;
  t.actuator = index;
  const std::array<double, 3> attach = Eval(a.attach2, v), pull = Eval(a.pull, v);
  t.max = Eval(a.max_force, v);
  const double norm = std::sqrt(pull[0] * pull[0] + pull[1] * pull[1] + pull[2] * pull[2]);
  if (!(norm > 0) || !(t.max > 0) || !std::isfinite(t.max))
    return absl::InvalidArgumentError(absl::StrCat(
        a.mark.ToString(), ": tendon ", a.name, " needs a non-zero pull and max_force > 0"));
  // The moment per newton in the end body's frame: attach x (pull / |pull|).
  t.arm = {(attach[1] * pull[2] - attach[2] * pull[1]) / norm,
           (attach[2] * pull[0] - attach[0] * pull[2]) / norm,
           (attach[0] * pull[1] - attach[1] * pull[0]) / norm};
  t.end = bodies_[Locate(BodyIndex(a.body2), attach).first];
  const int base = BodyIndex(a.body1);
  t.base = base < 0 ? nullptr : bodies_[built_[base].first];
  tendons_.push_back(t);
  return absl::OkStatus();
}

void GenericWorld::ApplyTendons(const std::vector<double>& commands) {
  for (const Tendon& t : tendons_) {
    const size_t i = static_cast<size_t>(t.actuator);
    const double f = i < commands.size() ? std::clamp(commands[i], -t.max, t.max) : 0.0;
    if (f == 0) continue;
    dVector3 w;  // the moment in the world frame
    dBodyVectorToWorld(t.end, f * t.arm[0], f * t.arm[1], f * t.arm[2], w);
    dBodyAddTorque(t.end, w[0], w[1], w[2]);
    if (t.base) dBodyAddTorque(t.base, -w[0], -w[1], -w[2]);
  }
}

}  // namespace gaitforge::generic
