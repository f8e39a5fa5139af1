// Paper 004's adaptive model on its arm: a learned map from the state to the joints'
// parameters drives the world (ParamValues::SetLearned), bad maps are refused, and an
// adaptive model learned from hold recordings of a state-dependent reference
// (workers/models/generic/generic_adaptive.h) follows a held-out hold better than the
// constant model fitted to the same recordings.
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "gtest/gtest.h"
#include "robots/registry.h"
#include "workers/models/generic/generic_adaptive.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::generic {
namespace {

const robots::RobotDescriptor& Arm() { return robots::Robot("continuum_arm"); }

const std::vector<std::string> kP = {"joint.stiffness_x_nm_per_rad", "joint.stiffness_y_nm_per_rad",
                                     "joint.damping_x_nms_per_rad", "joint.damping_y_nms_per_rad"};

// The reference's concealed map: as the tip rises (the arm bends) the stiffness falls by up
// to 30% and the damping rises by up to 50% (one logistic unit on tip.z).
std::shared_ptr<const learned::Mlp> Softening(double fall = 0.3) {
  learned::Mlp m;
  m.inputs = {"tip.x", "tip.y", "tip.z"};
  m.outputs = kP;
  m.in_mean = Eigen::Vector3d(0, 0, -0.285);
  m.in_sd = Eigen::Vector3d(1, 1, 0.005);
  m.out_mean = Eigen::Vector4d(0.1008, 0.1085, 0.0218, 0.0298);
  m.out_sd = Eigen::Vector4d::Ones();
  m.layers.push_back({Eigen::RowVector3d(0, 0, 1), Eigen::VectorXd::Zero(1)});
  m.layers.push_back({Eigen::Vector4d(-fall * 0.1008, -fall * 0.1085, 0.5 * 0.0218, 0.5 * 0.0298),
                      Eigen::VectorXd::Zero(4)});
  return std::make_shared<learned::Mlp>(m);
}

// A playback recording of the arm (values v) under rod forces eased in over 0.3 s whose
// resultant pulls towards `direction` (rad) with `magnitude` N (rod k: 2/3 of it times the
// cosine from its angle, pulling or pushing), held to 1.2 s: tip and forces at 100 Hz.
recording::Recording Hold(const ParamValues& v, double direction, double magnitude) {
  auto w = GenericWorld::Build(Arm(), v, 0);
  EXPECT_TRUE(w.ok()) << w.status();
  recording::Recording rec;
  rec.channels = {"tip.x", "tip.y", "tip.z", "rod1.force", "rod2.force", "rod3.force"};
  rec.columns.resize(6);
  rec.dt = 0.01;
  rec.meta.robot = "continuum_arm";
  rec.meta.command_kind = "playback";
  const double h = (*w)->timestep();
  for (int i = 0; i <= std::lround(1.2 / h); ++i) {
    const double t = i * h;
    std::vector<double> f;
    for (int k = 0; k < 3; ++k)
      f.push_back(2.0 / 3 * magnitude * std::min(1.0, t / 0.3) * std::cos(direction - 2.0944 * k));
    if (i % std::lround(0.01 / h) == 0) {
      rec.t.push_back(t);
      rec.columns[0].push_back(*(*w)->Channel("tip.x"));
      rec.columns[1].push_back(*(*w)->Channel("tip.y"));
      rec.columns[2].push_back(*(*w)->Channel("tip.z"));
      for (int k = 0; k < 3; ++k) rec.columns[3 + k].push_back(f[k]);
    }
    EXPECT_TRUE((*w)->Step(f).ok);
  }
  return rec;
}

class ArmAdaptiveTest : public ::testing::Test {
 protected:
  void SetUp() override { sim::InitThread(); }
};

TEST_F(ArmAdaptiveTest, ALearnedMapSetsTheJointsFromTheState) {
  ParamValues nominal(Arm()), softening(Arm()), flat(Arm());
  softening.SetLearned(Softening());
  flat.SetLearned(Softening(0));  // the stiffness as it is; only the damping grows
  const double x0 = Hold(nominal, 0, 3).columns[0].back();
  const double xs = Hold(softening, 0, 3).columns[0].back();
  const double xf = Hold(flat, 0, 3).columns[0].back();
  EXPECT_GT(xs, x0 + 0.005);  // softer as it bends: it bends further
  EXPECT_LT(std::abs(xf - x0), 0.3 * (xs - x0));  // damping alone: about where it was
}

TEST_F(ArmAdaptiveTest, AMapThatNamesNoChannelOrNoParameterIsRefused) {
  auto bad_input = std::make_shared<learned::Mlp>(*Softening());
  bad_input->inputs[2] = "tip.w.rate";
  ParamValues v(Arm());
  v.SetLearned(bad_input);
  auto w = GenericWorld::Build(Arm(), v, 0);
  ASSERT_FALSE(w.ok());
  EXPECT_NE(std::string(w.status().message()).find("learned model: input 'tip.w.rate' is not a channel of continuum_arm"),
            std::string::npos) << w.status();
  auto bad_output = std::make_shared<learned::Mlp>(*Softening());
  bad_output->outputs[0] = "joint.stiffness_z";
  v.SetLearned(bad_output);
  EXPECT_FALSE(GenericWorld::Build(Arm(), v, 0).ok());
}

TEST_F(ArmAdaptiveTest, TheAdaptiveModelFollowsAHeldOutHoldBetterThanTheConstantOne) {
  ParamValues reference(Arm());
  reference.SetLearned(Softening());
  std::vector<recording::Recording> recs;
  for (int k = 0; k < 4; ++k)
    for (double magnitude : {1.0, 1.75, 2.5, 3.25}) recs.push_back(Hold(reference, k * M_PI / 2, magnitude));
  std::vector<const recording::Recording*> ptrs;
  for (const auto& r : recs) ptrs.push_back(&r);
  learned::TrainOptions train;
  train.test_fraction = 0;
  auto m = LearnAdaptiveModel(Arm(), ParamValues(Arm()), ptrs, {"tip.x", "tip.y", "tip.z"}, kP, 40,
                              train, 2);
  ASSERT_TRUE(m.ok()) << m.status();
  // Fitted on the hold, the stiffness about y falls with the pull towards +x (rod 1).
  EXPECT_LT(m->per_recording[3].values[1], m->per_recording[0].values[1] - 0.01);
  const recording::Recording held_out = Hold(reference, M_PI / 2, 2.1);  // between two magnitudes
  ParamValues constant(Arm()), adaptive(Arm());
  for (size_t i = 0; i < kP.size(); ++i) ASSERT_TRUE(constant.Set(kP[i], m->constant.values[i]).ok());
  adaptive.SetLearned(std::make_shared<learned::Mlp>(m->mlp));
  const double e_constant = PlaybackError(Arm(), constant, held_out);
  const double e_adaptive = PlaybackError(Arm(), adaptive, held_out);
  EXPECT_LT(e_adaptive, 0.7 * e_constant) << e_adaptive << " vs " << e_constant;
}

}  // namespace
}  // namespace gaitforge::generic
