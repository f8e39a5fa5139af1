// The motors' electrical power (power_meter.h).
#include "workers/models/generic/power_meter.h"

#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>

#include "absl/strings/str_cat.h"
#include "robots/registry.h"
#include "workers/models/generic/generic_world.h"

namespace gaitforge::generic {
namespace {

// The model file's text and a name for messages: the built-in robot's embedded file, else
// the file beside the descriptor.
absl::StatusOr<std::pair<std::string, std::string>> ModelText(const robots::RobotDescriptor& d) {
  const std::string& file = d.electrical->current_model;
  if (std::string_view text = robots::BuiltinFile(d.name, file); !text.empty())
    return std::pair{std::string(text), absl::StrCat("robots/", d.name, "/", file)};
  const std::filesystem::path path = std::filesystem::path(d.source).parent_path() / file;
  std::ifstream in(path);
  if (!in)
    return absl::NotFoundError(absl::StrCat(
        d.electrical->mark.ToString(), ": electrical.current_model: cannot read ", path.string(),
        " (a built-in robot's file, or one beside the descriptor's file on every worker)"));
  std::ostringstream s;
  s << in.rdbuf();
  return std::pair{s.str(), path.string()};
}

}  // namespace

absl::StatusOr<std::shared_ptr<const learned::Mlp>> CurrentModel(const robots::RobotDescriptor& d) {
  static std::mutex mu;
  static std::map<std::string, std::shared_ptr<const learned::Mlp>> cache;
  auto text = ModelText(d);
  if (!text.ok()) return text.status();
  std::lock_guard<std::mutex> lock(mu);
  if (auto it = cache.find(text->second); it != cache.end()) return it->second;
  auto mlp = learned::Mlp::FromJson(text->first, text->second);
  if (!mlp.ok()) return mlp.status();
  auto shared = std::make_shared<const learned::Mlp>(std::move(*mlp));
  cache[text->second] = shared;
  return shared;
}

absl::Status PowerMeter::UseModel(const robots::RobotDescriptor& d) {
  auto mlp = CurrentModel(d);
  if (!mlp.ok()) return mlp.status();
  const std::string where =
      absl::StrCat(d.electrical->mark.ToString(), ": electrical.current_model ",
                   d.electrical->current_model, ": ");
  if ((*mlp)->outputs != std::vector<std::string>{"bus.current"})
    return absl::InvalidArgumentError(where + "its one output must be bus.current (A)");
  for (const std::string& in : (*mlp)->inputs) {
    const size_t dot = in.rfind('.');
    const std::string base = in.substr(0, dot == std::string::npos ? 0 : dot);
    const std::string field = dot == std::string::npos ? "" : in.substr(dot + 1);
    int index = -1;
    for (size_t i = 0; i < d.actuators.size(); ++i)
      if (d.actuators[i].name == base && d.actuators[i].type == "servo")
        index = static_cast<int>(i);
    if (index < 0 || (field != "torque" && field != "rate"))
      return absl::InvalidArgumentError(absl::StrCat(
          where, "input '", in, "' is not a servo's torque or rate (SERVO.torque, SERVO.rate)"));
    inputs_.emplace_back(index, field == "rate");
  }
  mlp_ = *mlp;
  x_.resize(static_cast<Eigen::Index>(inputs_.size()));
  return absl::OkStatus();
}

absl::StatusOr<std::unique_ptr<PowerMeter>> PowerMeter::For(const robots::RobotDescriptor& d,
                                                            const ParamValues& v) {
  if (!d.electrical) return nullptr;
  const robots::Electrical& e = *d.electrical;
  const auto value = [&v](const std::string& n) { return v(n); };
  auto m = std::make_unique<PowerMeter>();
  m->voltage_ = e.bus_voltage.Eval(value);
  m->standby_ = e.standby_current.Eval(value);
  m->regen_ = e.regen_efficiency.Eval(value);
  for (const robots::Electrical::Motor& motor : e.motors)
    for (const std::string& name : motor.actuators)
      for (size_t i = 0; i < d.actuators.size(); ++i)
        if (d.actuators[i].name == name)
          m->drives_.push_back({static_cast<int>(i), motor.gear.Eval(value), motor.kt.Eval(value),
                                motor.resistance.Eval(value)});
  if (!e.current_model.empty()) {
    if (absl::Status s = m->UseModel(d); !s.ok()) return s;
    m->sample_period_s_ = 1.0 / e.current_model_rate_hz.Eval(value);
  }
  return m;
}

double PowerMeter::MotorPower(const std::vector<double>& torque,
                              const std::vector<double>& rate) const {
  double p = voltage_ * standby_;
  for (const Drive& dr : drives_) {
    const double tau = torque[dr.actuator], current = tau / (dr.gear * dr.kt);
    p += tau * rate[dr.actuator] + 1.5 * dr.resistance * current * current;
  }
  return p < 0 ? regen_ * p : p;
}

double PowerMeter::Power(const std::vector<double>& torque, const std::vector<double>& rate) const {
  if (!mlp_) return MotorPower(torque, rate);
  for (size_t k = 0; k < inputs_.size(); ++k)
    x_[static_cast<Eigen::Index>(k)] =
        inputs_[k].second ? rate[inputs_[k].first] : torque[inputs_[k].first];
  return voltage_ * mlp_->Eval(x_)[0];
}

void PowerMeter::Step(const std::vector<double>& torque, const std::vector<double>& rate,
                      double h) {
  if (!mlp_) {
    energy_j_ += Power(torque, rate) * h;
  } else {
    // Sampled as the model's recordings were; a tolerance of a part in 1e9 of a period
    // keeps a step that lands on a sample time from slipping to the next.
    const double tolerance = 1e-9 * sample_period_s_;
    if (seconds_ >= next_sample_s_ - tolerance) {
      held_power_ = Power(torque, rate);
      while (next_sample_s_ <= seconds_ + tolerance) next_sample_s_ += sample_period_s_;
    }
    energy_j_ += held_power_ * h;
  }
  seconds_ += h;
}

}  // namespace gaitforge::generic
