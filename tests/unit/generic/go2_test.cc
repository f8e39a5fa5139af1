// Paper 002's Go2 on castors as data (robots/go2_castors/robot.yaml): it stands on its four
// feet, the PD joints holding the stand with a sag that their stiffness sets; with its legs
// folded it rests on its four castors at the paper's torso height, and they roll freely (on
// a slope it accelerates at g sin s, as on ice); on them it slides forwards by paper 002's
// paddling gait (leg_gait: left and right legs in phase, the front pair half a cycle after
// the rear), straight and at most its commanded speed; and it trots at paper 002's period
// for 10 s, balanced by the stance controller (robots/leg_stance.h).
#include <cmath>
#include <string>
#include <vector>

#include "gtest/gtest.h"
#include "robots/registry.h"
#include "workers/models/generic/generic_gait.h"
#include "workers/models/generic/generic_world.h"
#include "workers/models/mujoco/mujoco_world.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::generic {
namespace {

const robots::RobotDescriptor& Go2() { return robots::Robot("go2_castors"); }

class Go2Test : public ::testing::Test {
 protected:
  void SetUp() override { sim::InitThread(); }
};

// The thigh joints' height in the stand as built (m): the foot's radius under the leg.
double BuiltHeight(const ParamValues& v) {
  return v("foot.radius_m") + 0.764842 * v("calf.length_m") + 0.696707 * v("thigh.length_m");
}

// The torso's height (m) after `steps` of the same commands.
double Settle(GenericWorld& w, const std::vector<double>& commands, int steps) {
  for (int i = 0; i < steps; ++i) {
    const auto out = w.Step(commands);
    EXPECT_TRUE(out.ok) << out.reason;
    if (!out.ok) break;
  }
  return *w.Channel("torso.z");
}

// Thighs back and up (+1.2 rad from the stand) and calves folded (-1.2 rad, near their
// stop): the feet clear the floor by about 2 cm once the body rests on its castors.
std::vector<double> Folded() {
  std::vector<double> c(12, 0.0);
  for (int leg = 0; leg < 4; ++leg) {
    c[3 * leg + 1] = 1.2;
    c[3 * leg + 2] = -1.2;
  }
  return c;
}

TEST_F(Go2Test, StandsOnItsFeetSaggingByItsJointsStiffness) {
  double sag[2], tilt[2];
  for (int k = 0; k < 2; ++k) {
    ParamValues v(Go2());
    ASSERT_TRUE(v.Set("motor.kp_nm_per_rad", k == 0 ? 30 : 300).ok());
    auto w = GenericWorld::Build(Go2(), v, 0);
    ASSERT_TRUE(w.ok()) << w.status();
    sag[k] = BuiltHeight(v) - Settle(**w, std::vector<double>(12, 0.0), 2000);
    EXPECT_EQ((*w)->ground_contacts(), 4) << "the four feet, castors clear";
    tilt[k] = (*w)->max_tilt();
  }
  // 15.5 kg on PD joints without the stance's feed-forward: about 5 cm at kp 30, pitched
  // forward (its centre of mass lies 21 mm ahead of the hips' centre), and joints ten
  // times stiffer sag less than a tenth as much, level.
  EXPECT_GT(sag[0], 0.03);
  EXPECT_LT(sag[0], 0.08);
  EXPECT_LT(tilt[0], 0.2);
  EXPECT_LT(sag[1], 0.1 * sag[0]);
  EXPECT_LT(tilt[1], 0.01);
}

TEST_F(Go2Test, WithItsLegsFoldedItRestsOnItsCastorsAtThePapersHeight) {
  ParamValues v(Go2());
  auto w = GenericWorld::Build(Go2(), v, 0);
  ASSERT_TRUE(w.ok()) << w.status();
  const double z = Settle(**w, Folded(), 2000);
  // Torso centre 105 mm up when sliding (paper): here the castors' 51 mm support, half the
  // base's height and its centre of mass 5 mm under the hips' plane.
  EXPECT_NEAR(z, v("castor.support_m") + 0.5 * v("base.height_m") - v("base.com_z_m"), 0.002);
  EXPECT_EQ((*w)->ground_contacts(), 4) << "the four castors, feet clear";
}

TEST_F(Go2Test, ItsCastorsRollFreely) {
  ParamValues v(Go2());
  const double s = 0.05;
  ASSERT_TRUE(v.Set("effect.slope_rad", s).ok());
  auto w = GenericWorld::Build(Go2(), v, 0);
  ASSERT_TRUE(w.ok()) << w.status();
  Settle(**w, Folded(), 1500);
  double x[3];
  for (double& xi : x) {
    Settle(**w, Folded(), 500);
    xi = *(*w)->Channel("torso.x");
  }
  const double a = (x[2] - 2 * x[1] + x[0]) / (0.5 * 0.5);
  EXPECT_NEAR(a, -v("simulation.gravity_m_per_s2") * std::sin(s), 0.03 * 9.81 * std::sin(s));
}

// The channel `name` of a run.
std::vector<double> Column(const calibration::SimRun& run, const std::string& name) {
  const auto& tr = run.trajectory;
  for (size_t c = 0; c < tr.channels.size(); ++c)
    if (tr.channels[c] == name) return tr.columns[c];
  ADD_FAILURE() << name;
  return {};
}

TEST_F(Go2Test, ItTrotsAtThePapersPeriodForTenSeconds) {
  ParamValues v(Go2());
  // T 0.6 s, stance 0.5, lift 0.08 m (paper), 0.22 m/s; thigh joints 0.30 m over the feet,
  // all the weight on the feet; diagonal pairs (lr 0.5, fh 0.5).
  const auto run = SimulateChannels(Go2(), v, {0.6, 0.5, 0.08, 0.22, 0.30, 1, 0.5, 0.5}, 16, 50);
  ASSERT_TRUE(run.valid) << run.reason;
  const auto x = Column(run, "torso.x"), z = Column(run, "torso.z");
  const double t = run.trajectory.t.back() - run.trajectory.t.front();
  ASSERT_GE(t, 9.5);
  for (double zi : z) {  // up on its legs throughout: it never falls
    EXPECT_GT(zi, 0.29);
    EXPECT_LT(zi, 0.35);
  }
  const double speed = (x.back() - x.front()) / t;
  EXPECT_GT(speed, 0.4 * 0.22);  // forwards, short of the commanded speed (docs/robots.md)
  EXPECT_LT(speed, 1.05 * 0.22);
}

TEST_F(Go2Test, ItSlidesOnItsCastorsByPaddling) {
  ParamValues v(Go2());
  // Paper 002's slide at its slowest speed: T 0.8 s, stance 0.6, lift 0.03 m, 0.16 m/s; the
  // thigh joints 0.1 m over the feet (the base rests on its castors), the stance feet
  // carrying 30% of the weight; lr 0, fh 0.5.
  const auto run = SimulateChannels(Go2(), v, {0.8, 0.6, 0.03, 0.16, 0.1, 0.3, 0, 0.5}, 10, 50,
                                    0, {}, 1);
  ASSERT_TRUE(run.valid) << run.reason;
  const auto& tr = run.trajectory;
  const auto x = Column(run, "torso.x"), y = Column(run, "torso.y"), z = Column(run, "torso.z");
  const double speed = (x.back() - x.front()) / (tr.t.back() - tr.t.front());
  EXPECT_GT(speed, 0.5 * 0.16);
  EXPECT_LT(speed, 1.05 * 0.16);
  EXPECT_NEAR(y.back(), 0, 0.01);  // straight: its legs move in mirror pairs
  const double rest = v("castor.support_m") + 0.5 * v("base.height_m") - v("base.com_z_m");
  for (double zi : z) EXPECT_NEAR(zi, rest, 0.012);  // on its castors throughout
}

// A gait out of the legs' reach is an invalid evaluation with the reason, not a run of
// bent legs counted as travel.
TEST_F(Go2Test, AGaitOutOfReachIsInvalidWithTheReason) {
  ParamValues v(Go2());
  const auto run = SimulateChannels(Go2(), v, {1.5, 0.8, 0.12, 0.5, 0.40, 1, 0.5, 0.5}, 1, 50);
  EXPECT_FALSE(run.valid);
  EXPECT_NE(run.reason.find("the foot's path leaves the leg's reach"), std::string::npos) << run.reason;
}

// A fall is an invalid run with the reason, never travel: past simulation.fall_tilt_rad (1
// rad on the Go2; here set below the trot's own 0.04 rad of tilt to make it fall).
TEST_F(Go2Test, AFallIsInvalidWithTheReason) {
  ParamValues v(Go2());
  ASSERT_TRUE(v.Set("simulation.fall_tilt_rad", 0.02).ok());
  GaitOptions o;
  o.settle_cycles = 1;
  o.measured_cycles = 2;
  const GaitResult g = EvaluateGait(Go2(), v, {0.6, 0.5, 0.08, 0.22, 0.30, 1, 0.5, 0.5}, o);
  EXPECT_FALSE(g.valid);
  EXPECT_NE(g.reason.find("fell: base tilted"), std::string::npos) << g.reason;
  EXPECT_NE(g.reason.find("(> simulation.fall_tilt_rad = 0.02)"), std::string::npos) << g.reason;
}

// The same descriptor built in MuJoCo (another contact law, integrator and actuator): the
// trot and the slide go the same way at about the same speed.
TEST_F(Go2Test, ItsMujocoBuildTrotsAndSlidesAlike) {
  ParamValues v(Go2());
  const WorldBuilder mujoco = [](const robots::RobotDescriptor& d, const ParamValues& values,
                                 double h) -> absl::StatusOr<std::unique_ptr<RobotWorld>> {
    auto w = mujoco::MujocoWorld::Build(d, values, h);
    if (!w.ok()) return w.status();
    return std::unique_ptr<RobotWorld>(std::move(*w));
  };
  for (const std::vector<double>& genes : {std::vector<double>{0.6, 0.5, 0.08, 0.22, 0.30, 1, 0.5, 0.5},
                                           std::vector<double>{0.8, 0.6, 0.03, 0.16, 0.1, 0.3, 0, 0.5}}) {
    double speed[2];
    for (int k = 0; k < 2; ++k) {
      const auto run = SimulateChannels(Go2(), v, genes, 8, 50, 0, k ? mujoco : WorldBuilder{}, 1);
      ASSERT_TRUE(run.valid) << run.reason;
      const auto x = Column(run, "torso.x");
      speed[k] = (x.back() - x.front()) / (run.trajectory.t.back() - run.trajectory.t.front());
    }
    EXPECT_GT(speed[1], 0.05) << genes[0];
    EXPECT_NEAR(speed[1], speed[0], 0.3 * speed[0]) << genes[0];
  }
}

// Paper 002's finding on the battery (robots/go2_castors/robot.yaml, `electrical:`, its
// learned current model): sliding on the castors costs a fraction of trotting's electrical
// energy per metre at the paper's slowest commanded speed, 0.16 m/s (20 cycles, README.md:
// trot 6.5-6.9, slide 1.5-1.6; the paper's 6.06-6.24 and 1.07-1.12); both draw more than
// the standby power.
TEST_F(Go2Test, SlidingCostsLessBatteryEnergyPerMetreThanTrotting) {
  ParamValues v(Go2());
  GaitOptions o;
  o.settle_cycles = 2;
  o.measured_cycles = 6;
  const GaitResult trot = EvaluateGait(Go2(), v, {0.6, 0.5, 0.08, 0.16, 0.30, 1, 0.5, 0.5}, o);
  const GaitResult slide = EvaluateGait(Go2(), v, {0.8, 0.6, 0.03, 0.16, 0.1, 0.3, 0, 0.5}, o);
  for (const GaitResult* g : {&trot, &slide}) {
    ASSERT_TRUE(g->valid) << g->reason;
    ASSERT_TRUE(g->electrical);
    ASSERT_GT(g->travel_m, 0);
  }
  const double standby_w = v("power.bus_voltage_v") * v("power.standby_current_a");
  const auto power = [](const GaitResult& g) { return g.electrical_energy_j / g.measured_s; };
  const auto cot = [](const GaitResult& g) {
    return g.electrical_energy_j / (g.weight_n * g.travel_m);
  };
  EXPECT_GT(power(slide), standby_w);
  EXPECT_GT(power(trot), power(slide));
  EXPECT_LT(cot(slide), 0.5 * cot(trot))
      << "trot " << cot(trot) << " (" << power(trot) << " W), slide " << cot(slide) << " ("
      << power(slide) << " W)";
}

// Paper 002's reality gap as the robot's own suspects (the gap finder tries them beside its
// catalog): a torque factor on the motors (scale.motor_torque, their PD gains and limits)
// and Coulomb plus viscous joint friction. Either one costs the trot travel.
TEST_F(Go2Test, PaperTwosRealityGapIsItsSuspectsAndEachCostsTravel) {
  ASSERT_EQ(Go2().suspects.size(), 2u);
  EXPECT_EQ(Go2().suspects[0].id, "motor.torque_factor");
  EXPECT_EQ(Go2().suspects[1].id, "joint.friction");
  const std::vector<double> trot = {0.6, 0.5, 0.08, 0.25, 0.30, 1, 0.5, 0.5};
  const auto travel = [&](const std::vector<std::pair<std::string, double>>& set) {
    ParamValues v(Go2());
    for (const auto& [name, value] : set) EXPECT_TRUE(v.Set(name, value).ok()) << name;
    const auto r = SimulateChannels(Go2(), v, trot, 4, 50);
    EXPECT_TRUE(r.valid) << r.reason;
    const auto x = Column(r, "torso.x");
    return x.back() - x.front();
  };
  const double nominal = travel({});
  EXPECT_LT(travel({{"scale.motor_torque", 0.6}}), nominal - 0.03) << nominal;
  EXPECT_LT(travel({{"joint.friction_nm", 0.8}, {"joint.damping_nms_per_rad", 0.3}}),
            nominal - 0.005)
      << nominal;
}

}  // namespace
}  // namespace gaitforge::generic
