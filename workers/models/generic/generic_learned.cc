// GenericWorld's learned parameter map (generic_world.h, ParamValues::SetLearned; paper
// 004's adaptive model): every step the map's inputs are read from the channels, its
// outputs set as parameters (held in their ranges), and the joints' springs and dampers
// re-read from them.
#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/strings/match.h"
#include "workers/models/generic/generic_world.h"

namespace gaitforge::generic {

absl::Status GenericWorld::BuildLearned(const ParamValues& v) {
  if (!v.learned()) return absl::OkStatus();
  Learned l;
  l.mlp = v.learned();
  const std::vector<std::string> channels = d_.Channels();
  for (const std::string& input : l.mlp->inputs) {
    const bool rate = absl::EndsWith(input, ".rate");
    const std::string channel = rate ? input.substr(0, input.size() - 5) : input;
    if (std::find(channels.begin(), channels.end(), channel) == channels.end())
      return absl::InvalidArgumentError(absl::StrCat(
          "learned model: input '", input, "' is not a channel of ", d_.name,
          " (nor one with .rate); its channels: ", absl::StrJoin(channels, ", ")));
    l.channels.push_back(channel);
    l.rate.push_back(rate);
  }
  for (const std::string& output : l.mlp->outputs) {
    const robots::Parameter* p = d_.FindParameter(output);
    if (p == nullptr)
      return absl::InvalidArgumentError(absl::StrCat("learned model: output '", output,
                                                     "' is not a parameter of ", d_.name));
    l.outputs.push_back(p);
  }
  l.values = std::make_unique<ParamValues>(v);
  learned_ = std::move(l);
  return absl::OkStatus();
}

void GenericWorld::ApplyLearned() {
  if (!learned_) return;
  Learned& l = *learned_;
  std::vector<double> now, x;
  for (size_t i = 0; i < l.channels.size(); ++i) now.push_back(*Channel(l.channels[i]));
  if (l.previous.empty()) l.previous = now;  // at rest: no rate yet
  for (size_t i = 0; i < now.size(); ++i) x.push_back(l.rate[i] ? (now[i] - l.previous[i]) / h_ : now[i]);
  l.previous = now;
  const std::vector<double> y = (*l.mlp)(x);
  for (size_t k = 0; k < y.size(); ++k) {
    const robots::Parameter& p = *l.outputs[k];
    const double held = std::clamp(std::isfinite(y[k]) ? y[k] : p.value, p.lo, p.hi);
    (void)l.values->Set(p.name, held);  // in range; a relation it breaks keeps the last value
  }
  for (size_t i = 0; i < joints_.size(); ++i) {
    if (d_.joints[i].type != "universal" && d_.joints[i].type != "hinge") continue;
    const Spring s = SpringOf(d_.joints[i], *l.values);
    if (d_.joints[i].type == "hinge") {
      springs_[i] = s;
      continue;
    }
    springs_[i].k = s.k;
    springs_[i].k2 = s.k2;
    for (UniversalDamper& u : universal_dampers_) {
      if (u.joint != joints_[i]) continue;
      u.c1 = s.c;
      u.c2 = s.c2;
      if (s.c > 0) dJointSetAMotorParam(u.motor, dParamCFM, 1 / s.c);
      if (s.c2 > 0) dJointSetAMotorParam(u.motor, dParamCFM2, 1 / s.c2);
    }
  }
}

}  // namespace gaitforge::generic
