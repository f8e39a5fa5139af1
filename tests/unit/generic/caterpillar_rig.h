#pragma once
// Test rigs cut from the caterpillar's built-in descriptor (robots/caterpillar/robot.yaml)
// for the generic builder's physical tests: some of its lumps, the links between them, the
// pistons that span two kept lumps, with or without the ground, and gravity by parameter.
// The cut is made on the descriptor's text, so the rig is built by the same code as the
// robot, with no test-only switch in the builder.
#include <cstdint>
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "gtest/gtest.h"
#include "robots/descriptor_parser.h"
#include "robots/registry.h"
#include "workers/models/generic/generic_world.h"
#include "workers/models/generic/param_eval.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::generic::testing {

struct Cut {
  int first = 1, last = 6;  // lumps kept (1 rear .. 6 front)
  bool actuators = true;    // the pistons spanning two kept lumps
  bool ground = true;
  bool gravity = true;      // false: simulation.gravity_m_per_s2 = 0
};

// A cut of no lumps, links or pistons: the robot in free space.
inline Cut FreeChain(int first = 1, int last = 6) { return {first, last, false, false, false}; }

// Keeps the entries of a sequence whose `key` names pass `keep`.
inline YAML::Node Filter(const YAML::Node& seq, const std::function<bool(const YAML::Node&)>& keep) {
  YAML::Node out(YAML::NodeType::Sequence);
  for (const auto& n : seq)
    if (keep(n)) out.push_back(n);
  return out;
}

inline robots::RobotDescriptor CutDescriptor(const Cut& cut) {
  YAML::Node root = YAML::Load(std::string(robots::BuiltinText("caterpillar")));
  std::set<std::string> lumps;
  for (int i = cut.first; i <= cut.last; ++i) lumps.insert("lump" + std::to_string(i));
  auto both_kept = [&](const YAML::Node& n) {
    return lumps.count(n["bodies"][0].as<std::string>()) && lumps.count(n["bodies"][1].as<std::string>());
  };
  root["bodies"] = Filter(root["bodies"], [&](const YAML::Node& b) {
    return lumps.count(b["name"].as<std::string>()) > 0;
  });
  root["joints"] = Filter(root["joints"], both_kept);
  YAML::Node names(YAML::NodeType::Sequence);
  if (cut.actuators) {
    root["actuators"] = Filter(root["actuators"], both_kept);
    for (const auto& a : root["actuators"]) names.push_back(a["name"]);
  }
  if (names.size() == 0) {
    root.remove("actuators");
    root["controller"] = YAML::Load("{kind: hold}");
  } else {
    root["controller"]["actuators"] = names;
  }
  if (!cut.ground) root.remove("ground");
  // The markers of the kept lumps.
  YAML::Node marker = root["sensors"][0];  // a handle: edits reach root
  YAML::Node kept_names(YAML::NodeType::Sequence), kept_bodies(YAML::NodeType::Sequence);
  for (size_t i = 0; i < marker["bodies"].size(); ++i)
    if (lumps.count(marker["bodies"][i].as<std::string>())) {
      kept_names.push_back(marker["names"][i]);
      kept_bodies.push_back(marker["bodies"][i]);
    }
  marker["names"] = kept_names;
  marker["bodies"] = kept_bodies;
  YAML::Emitter out;
  out << root;
  auto d = robots::ParseDescriptor(out.c_str(), "caterpillar rig");
  if (d.ok()) return *d;
  ADD_FAILURE() << d.status();
  return {};
}

// A built rig: its descriptor, parameter values and world (each at a stable address).
struct Rig {
  std::unique_ptr<robots::RobotDescriptor> d;
  std::unique_ptr<ParamValues> values;
  std::unique_ptr<GenericWorld> world;
  GenericWorld* operator->() const { return world.get(); }
  // Descriptor joint k's stiffnesses and damping ratios.
  double Value(const robots::Expr& e) const { return Eval(e, *values); }
  double operator()(const std::string& name) const { return (*values)(name); }
};

// `set` parameter values (each must be accepted) on the cut; h <= 0: the robot's timestep.
inline Rig MakeRig(const Cut& cut = {}, const std::vector<std::pair<std::string, double>>& set = {},
                   double h = 0) {
  sim::InitThread();
  Rig rig;
  rig.d = std::make_unique<robots::RobotDescriptor>(CutDescriptor(cut));
  rig.values = std::make_unique<ParamValues>(*rig.d);
  if (!cut.gravity) {
    EXPECT_TRUE(rig.values->Set("simulation.gravity_m_per_s2", 0).ok());
  }
  for (const auto& [name, value] : set) {
    const absl::Status s = rig.values->Set(name, value);
    EXPECT_TRUE(s.ok()) << s;
  }
  auto w = GenericWorld::Build(*rig.d, *rig.values, h);
  EXPECT_TRUE(w.ok()) << w.status();
  if (w.ok()) rig.world = std::move(*w);
  return rig;
}

// The rig's commands for an on/off mask over the full robot's pistons (bit j: T1 T2 T3 B1
// B2 B3), in the rig's descriptor order.
inline std::vector<double> Commands(const Rig& rig, uint32_t mask) {
  static const std::vector<std::string> kOrder = {"T1", "T2", "T3", "B1", "B2", "B3"};
  std::vector<double> c;
  for (const auto& a : rig.d->actuators) {
    size_t j = 0;
    while (j < kOrder.size() && kOrder[j] != a.name) ++j;
    c.push_back(j < kOrder.size() && (mask >> j & 1u) ? 1.0 : 0.0);
  }
  return c;
}

// Steps `seconds` with pistons `mask`; `before` runs before each step (to add loads) and
// `after` after it. Fails the test (and stops) if the model diverges.
inline void Simulate(Rig& rig, double seconds, uint32_t mask,
                     const std::function<void(Rig&)>& before = nullptr,
                     const std::function<void(Rig&)>& after = nullptr) {
  const int64_t steps = static_cast<int64_t>(seconds / rig->timestep() + 0.5);
  const std::vector<double> commands = Commands(rig, mask);
  for (int64_t i = 0; i < steps; ++i) {
    if (before) before(rig);
    const sim::SimOutcome o = rig->Step(commands);
    ASSERT_TRUE(o.ok) << o.reason;
    if (after) after(rig);
  }
}

// An ODE body's pitch about +y (rad; + turns +x towards -z).
inline double Pitch(dBodyID b) {
  const dReal* r = dBodyGetRotation(b);
  return std::atan2(-r[8], r[0]);
}

inline double MeanX(const Rig& rig) {
  double s = 0;
  for (int k = 0; k < rig->body_count(); ++k) s += rig->BodyCentre(k)[0];
  return s / rig->body_count();
}

// The kinetic energy of every ODE body (J).
inline double KineticEnergy(const GenericWorld& w) {
  double e = 0;
  for (int i = 0; i < w.ode_body_count(); ++i) {
    const dBodyID b = w.ode_body(i);
    dMass m;
    dBodyGetMass(b, &m);
    const dReal* v = dBodyGetLinearVel(b);
    const dReal* wv = dBodyGetAngularVel(b);
    dVector3 om;  // angular velocity in the body frame
    dBodyVectorFromWorld(b, wv[0], wv[1], wv[2], om);
    e += 0.5 * m.mass * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) e += 0.5 * om[r] * m.I[r * 4 + c] * om[c];
  }
  return e;
}

}  // namespace gaitforge::generic::testing
