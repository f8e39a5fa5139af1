#include "workers/models/mujoco/mujoco_world.h"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "absl/strings/str_cat.h"
#include "workers/models/mujoco/mjcf.h"

namespace gaitforge::mujoco {
namespace {

double Eval(const robots::Expr& e, const generic::ParamValues& v) {
  return e.Eval([&v](const std::string& n) { return v(n); });
}

// MuJoCo's default error handler exits the process; a worker must get a reason instead.
[[noreturn]] void Throw(const char* msg) { throw std::runtime_error(msg); }
void Warn(const char*) {}  // warnings are read from mjData::warning (CheckState)

// mj_loadXML from memory: the MJCF text as the one file of a virtual file system.
absl::StatusOr<mjModel*> Load(const std::string& xml, const std::string& source) {
  static std::once_flag once;
  std::call_once(once, [] {
    mju_user_error = Throw;
    mju_user_warning = Warn;
  });
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  const char* name = "robot.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), name, static_cast<int>(xml.size())) != 0)
    return absl::InternalError("MuJoCo: cannot hold the model in its virtual file system");
  std::copy(xml.begin(), xml.end(), static_cast<char*>(vfs->filedata[mj_findFileVFS(vfs.get(), name)]));
  char error[1000] = "";
  mjModel* m = nullptr;
  try {
    m = mj_loadXML(name, vfs.get(), error, sizeof error);
  } catch (const std::runtime_error& e) {
    snprintf(error, sizeof error, "%s", e.what());
  }
  mj_deleteVFS(vfs.get());
  if (!m) return absl::InvalidArgumentError(absl::StrCat(source, ": MuJoCo refused the model: ", error));
  return m;
}

}  // namespace

absl::StatusOr<std::unique_ptr<MujocoWorld>> MujocoWorld::Build(const robots::RobotDescriptor& d,
                                                                const generic::ParamValues& v,
                                                                double timestep_s) {
  const generic::BuilderEffects fx(v);
  if (fx.friction_forward != 0 || fx.friction_backward != 0)
    return absl::UnimplementedError(
        "the MuJoCo build has no direction-dependent friction (effect.friction_forward, "
        "effect.friction_backward)");
  if (fx.contact_slip != 0)
    return absl::UnimplementedError(
        "the MuJoCo build has no creeping contact (effect.contact_slip_m_per_n_s): its "
        "contact creeps by its own law");
  auto xml = ToMjcf(d, v, timestep_s);
  if (!xml.ok()) return xml.status();
  auto m = Load(*xml, d.source);
  if (!m.ok()) return m.status();
  std::unique_ptr<MujocoWorld> w(new MujocoWorld(d, v, (*m)->opt.timestep));
  w->m_ = *m;
  w->data_ = mj_makeData(w->m_);
  const double slope = w->fx_.slope, g = v("simulation.gravity_m_per_s2");
  w->m_->opt.gravity[0] = -g * std::sin(slope);
  w->m_->opt.gravity[2] = -g * std::cos(slope);
  for (const robots::Body& b : d.bodies) w->body_ids_.push_back(mj_name2id(w->m_, mjOBJ_BODY, b.name.c_str()));
  for (const robots::Actuator& a : d.actuators) {
    Servo s;
    s.joint = mj_name2id(w->m_, mjOBJ_JOINT, a.joint.c_str());
    s.qpos = w->m_->jnt_qposadr[s.joint];
    s.dof = w->m_->jnt_dofadr[s.joint];
    s.pd = a.kp.has_value();
    if (s.pd) {
      s.kp = Eval(*a.kp, v);
      s.kd = Eval(*a.kd, v);
    } else {
      s.gain = Eval(a.gain, v);
      s.max_speed = Eval(a.max_speed, v);
    }
    s.max_torque = Eval(a.max_torque, v);
    const double lag = Eval(a.lag_s, v);
    s.lag_keep = lag > 0 ? std::exp(-w->h_ / lag) : 0;
    s.extra_keep = w->fx_.actuator_lag > 0 ? std::exp(-w->h_ / w->fx_.actuator_lag) : 0;
    w->servos_.push_back(s);
  }
  w->actuator_torque_.assign(d.actuators.size(), 0.0);
  w->actuator_rate_.assign(d.actuators.size(), 0.0);
  for (const robots::Sensor& s : d.sensors) {
    if (s.kind != "marker" || s.bodies.empty()) continue;  // as the ODE build
    for (size_t i = 0; i < s.names.size(); ++i) {
      Marker mk{s.names[i], mj_name2id(w->m_, mjOBJ_BODY, s.bodies[i].c_str()), {}};
      for (int k = 0; k < 3; ++k) mk.offset[k] = s.offset ? Eval((*s.offset)[k], v) : 0.0;
      w->markers_.push_back(mk);
    }
  }
  w->max_speed_ = v("simulation.max_speed_m_per_s");
  w->max_excursion_ = v("simulation.max_excursion_m");
  mj_forward(w->m_, w->data_);
  for (int id : w->body_ids_)
    w->start_.push_back({w->data_->xpos[3 * id], w->data_->xpos[3 * id + 1], w->data_->xpos[3 * id + 2]});
  return w;
}

MujocoWorld::~MujocoWorld() {
  if (data_) mj_deleteData(data_);
  if (m_) mj_deleteModel(m_);
}

void MujocoWorld::SetServos(const std::vector<double>& commands) {
  for (size_t i = 0; i < servos_.size(); ++i) {
    Servo& s = servos_[i];
    const double target = i < commands.size() ? commands[i] : 0.0;
    s.extra = steps_ > 0 ? target + (s.extra - target) * s.extra_keep : target;
    s.command = steps_ > 0 ? s.extra + (s.command - s.extra) * s.lag_keep : s.extra;
    const double error = s.command - data_->qpos[s.qpos];
    const double drive = std::fabs(error) <= fx_.servo_deadband ? 0.0 : error;
    const double feed = servos_.size() + i < commands.size() ? commands[servos_.size() + i] : 0.0;
    data_->ctrl[i] = s.pd ? std::clamp(s.kp * drive - s.kd * data_->qvel[s.dof] + feed, -s.max_torque, s.max_torque)
                          : std::clamp(s.gain * drive, -s.max_speed, s.max_speed);
  }
}

void MujocoWorld::ApplyEffects() {
  std::fill(data_->xfrc_applied, data_->xfrc_applied + 6 * m_->nbody, 0.0);
  if (fx_.tether_force > 0 || fx_.tether_stiffness > 0) {
    const int id = body_ids_[0];
    const double travel = std::max(0.0, data_->xpos[3 * id] - start_[0][0]);
    data_->xfrc_applied[6 * id] -= fx_.tether_force + fx_.tether_stiffness * travel;
  }
  if (fx_.drag > 0)
    for (int id : body_ids_) {
      mjtNum vel[6];  // [angular; linear] at the body's centre of mass, world frame
      mj_objectVelocity(m_, data_, mjOBJ_XBODY, id, vel, 0);
      for (int k = 0; k < 3; ++k) data_->xfrc_applied[6 * id + k] -= fx_.drag * vel[3 + k];
    }
}

sim::SimOutcome MujocoWorld::CheckState() const {
  if (data_->warning[mjWARN_BADQACC].number > 0)
    return sim::SimOutcome::Failed(absl::StrCat("MuJoCo: bad acceleration (diverged) at t = ", time(), " s"));
  for (size_t i = 0; i < body_ids_.size(); ++i) {
    const int id = body_ids_[i];
    const mjtNum* p = data_->xpos + 3 * id;
    mjtNum vel[6];
    mj_objectVelocity(m_, data_, mjOBJ_XBODY, id, vel, 0);
    const double speed = std::sqrt(vel[3] * vel[3] + vel[4] * vel[4] + vel[5] * vel[5]);
    const std::string& name = d_.bodies[i].name;
    if (!std::isfinite(p[0] + p[1] + p[2]) || !std::isfinite(speed))
      return sim::SimOutcome::Failed(absl::StrCat("NaN in body ", name, " at t = ", time(), " s"));
    if (speed > max_speed_)
      return sim::SimOutcome::Failed(absl::StrCat("body ", name, " moves at ", speed,
                                                  " m/s (> simulation.max_speed_m_per_s) at t = ", time(), " s"));
    const double dx = p[0] - start_[i][0], dy = p[1] - start_[i][1], dz = p[2] - start_[i][2];
    if (std::sqrt(dx * dx + dy * dy + dz * dz) > max_excursion_)
      return sim::SimOutcome::Failed(absl::StrCat("body ", name,
                                                  " is farther than simulation.max_excursion_m from its start at t = ", time(), " s"));
  }
  return sim::SimOutcome::Ok();
}

sim::SimOutcome MujocoWorld::Step(const std::vector<double>& commands) {
  SetServos(commands);
  ApplyEffects();
  try {
    mj_step(m_, data_);
  } catch (const std::runtime_error& e) {
    return sim::SimOutcome::Failed(absl::StrCat("MuJoCo: ", e.what(), " at t = ", time(), " s"));
  }
  ++steps_;
  Observe();
  return CheckState();
}

void MujocoWorld::Observe() {
  const mjtNum* r = data_->xmat + 9 * body_ids_[0];
  const double pitch = std::atan2(r[2], r[8]), roll = std::atan2(r[5], r[8]);
  max_tilt_ = std::max({max_tilt_, std::fabs(pitch), std::fabs(roll)});
  for (size_t i = 0; i < servos_.size(); ++i) {
    const double torque = data_->actuator_force[i], rate = data_->qvel[servos_[i].dof];
    if (std::fabs(torque) >= 0.99 * servos_[i].max_torque) ++torque_limited_;
    servo_energy_ += std::max(0.0, torque * rate) * h_;
    actuator_torque_[i] = torque;
    actuator_rate_[i] = rate;
  }
}

std::array<double, 3> MujocoWorld::CentreOfMass() const {
  std::array<double, 3> c{};
  double total = 0;
  for (int id : body_ids_) {
    const double m = m_->body_mass[id];
    for (int k = 0; k < 3; ++k) c[k] += m * data_->xipos[3 * id + k];
    total += m;
  }
  for (double& x : c) x /= total;
  return c;
}

std::array<double, 3> MujocoWorld::BodyPosition(int i) const {
  const mjtNum* p = data_->xpos + 3 * body_ids_[i];
  return {p[0], p[1], p[2]};
}

robots::BodyState MujocoWorld::StateOf(int i) const {
  const int id = body_ids_[i];
  robots::BodyState s;
  s.position = BodyPosition(i);
  for (int k = 0; k < 9; ++k) s.rotation[k] = data_->xmat[9 * id + k];  // row-major
  mjtNum vel[6];  // [angular; linear] at the body's frame, world-oriented
  mj_objectVelocity(m_, data_, mjOBJ_BODY, id, vel, 0);
  for (int k = 0; k < 3; ++k) {
    s.spin[k] = vel[k];
    s.velocity[k] = vel[3 + k];
  }
  return s;
}

std::array<double, 3> MujocoWorld::JointAnchor(int j) const {
  const int id = mj_name2id(m_, mjOBJ_JOINT, d_.joints[j].name.c_str());
  if (id < 0) return {NAN, NAN, NAN};  // a fixed joint has no MuJoCo joint
  const mjtNum* p = data_->xanchor + 3 * id;
  return {p[0], p[1], p[2]};
}

double MujocoWorld::total_mass() const {
  double m = 0;
  for (int id : body_ids_) m += m_->body_mass[id];
  return m;
}

double MujocoWorld::torque_limited_fraction() const {
  const double n = static_cast<double>(steps_) * static_cast<double>(servos_.size());
  return n > 0 ? static_cast<double>(torque_limited_) / n : 0.0;
}

absl::StatusOr<double> MujocoWorld::Channel(const std::string& name) const {
  const size_t dot = name.rfind('.');
  const std::string base = name.substr(0, dot), field = dot == std::string::npos ? "" : name.substr(dot + 1);
  if (const robots::Joint* j = d_.FindJoint(base)) {
    const std::vector<std::string> fields = j->AngleFields();
    if (std::find(fields.begin(), fields.end(), field) != fields.end()) {
      // A hinge is the MuJoCo joint of its name; a universal joint is two hinges named
      // by their channels (mjcf.cc).
      const std::string mj = j->type == "hinge" ? base : name;
      return data_->qpos[m_->jnt_qposadr[mj_name2id(m_, mjOBJ_JOINT, mj.c_str())]];
    }
  }
  for (const Marker& mk : markers_) {
    if (mk.name != base || (field != "x" && field != "y" && field != "z")) continue;
    const int k = field[0] - 'x';
    const mjtNum* r = data_->xmat + 9 * mk.body;
    return data_->xpos[3 * mk.body + k] + r[3 * k] * mk.offset[0] + r[3 * k + 1] * mk.offset[1] +
           r[3 * k + 2] * mk.offset[2];
  }
  if (auto v = ActuatorChannel(d_, base, field)) return *v;
  return absl::NotFoundError(absl::StrCat(d_.name, " has no channel ", name));
}

generic::WorldBuilder Engine() {
  return [](const robots::RobotDescriptor& d, const generic::ParamValues& v,
            double timestep_s) -> absl::StatusOr<std::unique_ptr<generic::RobotWorld>> {
    auto w = MujocoWorld::Build(d, v, timestep_s);
    if (!w.ok()) return w.status();
    return std::unique_ptr<generic::RobotWorld>(std::move(*w));
  };
}

}  // namespace gaitforge::mujoco
