// Controller kinds (robots/controllers.h): the CPG's four coupled oscillators lock to the
// commanded pattern from any start, the stateful run gives the same commands however often
// it is asked, and a CPG must drive exactly four actuators.
#include <cmath>
#include <string>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "robots/controllers.h"
#include "robots/descriptor_parser.h"
#include "robots/registry.h"

namespace gaitforge::robots {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

// f, amp_front, amp_hind, off_front, off_hind, lr, fh, w
std::vector<double> Cpg(double lr, double fh) { return {1.0, 0.3, 0.2, 0.1, -0.1, lr, fh, 5.0}; }

// The phase of oscillator j less oscillator i's, less the pattern's, wrapped to (-pi, pi].
double Error(const std::vector<double>& phi, const std::vector<double>& g, int i, int j) {
  const double target[4] = {0, g[5], g[6], g[6] + g[5]};
  const double e = phi[j] - phi[i] - 2 * M_PI * (target[j] - target[i]);
  return std::remainder(e, 2 * M_PI);
}

TEST(Cpg, LocksToTheWalkAndTheBoundPatterns) {
  const Controller& c = Robot("tigrillo").controller;
  for (const auto& genes : {Cpg(0.5, 0.25), Cpg(0.0, 0.5), Cpg(0.5, 0.0)}) {
    ControllerRun run(c, genes);
    run.At(0.0);
    double start = 0;
    for (int j = 1; j < 4; ++j) start = std::max(start, std::fabs(Error(run.state(), genes, 0, j)));
    EXPECT_GT(start, 0.5);  // not locked at the start
    run.At(10.0);
    for (int j = 1; j < 4; ++j) EXPECT_NEAR(Error(run.state(), genes, 0, j), 0, 1e-6) << j;
    // The mean phase runs at exactly 2 pi f: the coupling terms cancel in pairs.
    double mean = 0;
    for (double p : run.state()) mean += p / 4;
    EXPECT_NEAR(mean, 2 * M_PI * (genes[0] * 10.0 + 0.15), 1e-6);
    // The commands are the phases' sines about the offsets.
    const std::vector<double> at = run.At(10.0);
    EXPECT_DOUBLE_EQ(at[2], genes[4] + genes[2] * std::sin(run.state()[2]));
  }
}

TEST(Cpg, ARunGivesTheSameCommandsHoweverOftenItIsAsked) {
  const Controller& c = Robot("tigrillo").controller;
  ControllerRun every_step(c, Cpg(0.5, 0.25));
  std::vector<double> stepped;
  for (int i = 0; i <= 3000; ++i) stepped = every_step.At(i * 1e-3);
  ControllerRun once(c, Cpg(0.5, 0.25));
  EXPECT_EQ(once.At(3.0), stepped);  // bit for bit
  const auto& kind = *FindControllerKind("cpg");
  EXPECT_EQ(kind.commands(c, Cpg(0.5, 0.25), 3.0), stepped);
}

TEST(Cpg, DrivesExactlyFourActuators) {
  std::string text = std::string(BuiltinText("tigrillo"));
  const std::string four = "actuators: [hip_fl, hip_fr, hip_hl, hip_hr]";
  text.replace(text.find(four), four.size(), "actuators: [hip_fl, hip_fr]");
  auto d = ParseDescriptor(text, "three.yaml");
  ASSERT_FALSE(d.ok());
  EXPECT_THAT(std::string(d.status().message()),
              AllOf(HasSubstr("three.yaml:"), HasSubstr("controller.actuators"),
                    HasSubstr("kind cpg drives exactly 4 actuators, got 2")));
}

TEST(SineSync, EachActuatorLeadsTheOneBeforeByLag) {
  const Controller& c = Robot("walker").controller;
  ControllerRun run(c, {2.0, 0.4, 0.1, 0.1});
  const double t = 0.37;
  const std::vector<double> at = run.At(t);
  EXPECT_DOUBLE_EQ(at[0], 0.1 + 0.4 * std::sin(2 * M_PI * (2.0 * t)));
  EXPECT_DOUBLE_EQ(at[1], 0.1 + 0.4 * std::sin(2 * M_PI * (2.0 * t + 0.1)));
}

}  // namespace
}  // namespace gaitforge::robots
