#include "robots/leg_gait.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_format.h"
#include "robots/leg_stance.h"

namespace gaitforge::robots {

std::array<double, 2> LegAngles(double thigh_m, double calf_m, double x, double z) {
  const double l1 = thigh_m, l2 = calf_m;
  double d = std::hypot(x, z);
  const double reach = std::clamp(d, std::fabs(l1 - l2) + 1e-9, l1 + l2 - 1e-9);
  if (d > 0) {
    x *= reach / d;
    z *= reach / d;
  } else {
    z = -reach;
  }
  d = reach;
  const double knee = -std::acos(std::clamp((d * d - l1 * l1 - l2 * l2) / (2 * l1 * l2), -1.0, 1.0));
  // The target's angle from straight down, less the foot's from the thigh's direction.
  const double target = std::atan2(-x, -z);
  const double foot = std::atan2(l2 * std::sin(knee), l1 + l2 * std::cos(knee));
  return {target - foot, knee};
}

std::vector<Gene> LegGaitGenes(const Controller& c) {
  auto g = [&](const char* name, const char* key) {
    const auto& r = c.ranges.at(key);
    return Gene{name, r[0], r[1]};
  };
  return {g("T", "period_s"),        g("stance", "stance_ratio"), g("lift", "lift_m"),
          g("speed", "speed_m_per_s"), g("height", "height_m"),     g("load", "load_share"),
          {"lr", 0, 1, true},          {"fh", 0, 1, true}};
}

double LegGaitPeriod(const std::vector<double>& genes) { return genes[0]; }

namespace {

// The stand's foot, ahead of (+) or behind the thigh joint (m): the stroke's centre.
double StandFootX(const Controller& c) {
  const double q1s = c.values.at("thigh_stand_rad"), q2s = c.values.at("calf_stand_rad");
  return -c.values.at("thigh_m") * std::sin(q1s) - c.values.at("calf_m") * std::sin(q1s + q2s);
}

}  // namespace

std::string LegGaitCheck(const Controller& c, const std::vector<double>& g) {
  const double l1 = c.values.at("thigh_m"), l2 = c.values.at("calf_m");
  const double x0 = StandFootX(c);
  const double stroke = g[3] * g[1] * g[0], height = g[4], lift = g[2];
  const struct {
    const char* where;
    double x, z;
  } points[] = {{"the stance stroke's front end", x0 + stroke / 2, -height},
                {"the stance stroke's back end", x0 - stroke / 2, -height},
                {"the swing's apex", x0, -height + lift}};
  for (const auto& p : points) {
    const double d = std::hypot(p.x, p.z);
    if (d > l1 + l2 || d < std::fabs(l1 - l2))
      return absl::StrFormat(
          "leg_gait: the foot's path leaves the leg's reach: at %s (%.3g m ahead of and %.3g m "
          "below the thigh joint) the foot is %.3g m from it, the leg reaches %.3g to %.3g m "
          "(speed x stance x T sets the stroke, height and lift its depth)",
          p.where, p.x, -p.z, d, std::fabs(l1 - l2), l1 + l2);
  }
  return "";
}

namespace {

// The foot's path at phase p in [0, 1): stance from +stroke/2 back to -stroke/2 on the
// ground, then a cycloid forwards and up by lift. Returns (x, height above the ground line).
std::array<double, 2> FootPath(double p, double stance, double stroke, double lift) {
  if (p < stance) return {stroke * (0.5 - p / stance), 0.0};
  const double s = (p - stance) / (1 - stance);
  constexpr double kTwoPi = 2 * M_PI;
  return {stroke * (s - std::sin(kTwoPi * s) / kTwoPi - 0.5), lift * 0.5 * (1 - std::cos(kTwoPi * s))};
}

}  // namespace

std::array<double, 2> StanceTorques(double l1, double l2, const std::array<double, 2>& q,
                                   double force) {
  // tau = -J^T (0, 0, F): the leg's own Jacobian (robots/leg_stance.h), in its plane.
  const LegPoint p = LegKinematics({0, 0, 0}, 0, 0, l1, l2, {0, q[0], q[1]});
  return {-force * p.jacobian[1][2], -force * p.jacobian[2][2]};
}

LegSchedule Schedule(const Controller& c, const std::vector<double>& g, double t) {
  const double l1 = c.values.at("thigh_m"), l2 = c.values.at("calf_m");
  const double q1s = c.values.at("thigh_stand_rad"), q2s = c.values.at("calf_stand_rad");
  const double x0 = StandFootX(c);
  const double period = g[0], stance = g[1], lift = g[2], speed = g[3], height = g[4];
  const double stroke = speed * stance * period;
  const double offset[4] = {0, g[6], g[7], g[7] + g[6]};  // FR, FL, RR, RL
  LegSchedule s;
  for (int leg = 0; leg < 4; ++leg) {
    const double ph = t / period + offset[leg];
    const double phase = ph - std::floor(ph);
    s.stance[leg] = phase < stance;
    s.on_ground += s.stance[leg];
    const auto [x, up] = FootPath(phase, stance, stroke, lift);
    s.q[leg] = LegAngles(l1, l2, x0 + x, -height + up);
    s.commands[3 * leg + 1] = s.q[leg][0] - q1s;
    s.commands[3 * leg + 2] = s.q[leg][1] - q2s;
  }
  return s;
}

std::vector<double> LegGaitCommands(const Controller& c, const std::vector<double>& g, double t) {
  const LegSchedule s = Schedule(c, g, t);
  // The stance feet share `load` of the weight evenly (paper 002's QP, closed form for
  // vertical forces; the castors carry the rest).
  const double force = g[5] * c.values.at("mass_kg") * kStandardGravity / std::max(1, s.on_ground);
  std::vector<double> out(s.commands.begin(), s.commands.end());
  out.resize(24, 0.0);
  for (int leg = 0; leg < 4; ++leg) {
    if (!s.stance[leg]) continue;
    const auto tau = StanceTorques(c.values.at("thigh_m"), c.values.at("calf_m"), s.q[leg], force);
    out[12 + 3 * leg + 1] = tau[0];
    out[12 + 3 * leg + 2] = tau[1];
  }
  return out;
}

}  // namespace gaitforge::robots
