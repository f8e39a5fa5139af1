// CMA-ES and the sweep end on their own criteria, before the spec's generations: the
// study says which one.
#include <gtest/gtest.h>

#include "tests/e2e/cluster.h"
#include "tests/support/temp_dir.h"

namespace gaitforge::testing {
namespace {

constexpr char kSpace[] = "objective: {name: analytic.sphere}\nbounds:\n"
                          "  - {lo: -1, hi: 1}\n  - {lo: -1, hi: 1}\n";

// Runs spec to its end on a fresh coordinator; returns watch's stderr and show's stdout.
std::pair<std::string, std::string> RunToTheEnd(const std::string& spec) {
  TempDir dir;
  WriteFile(dir.File("s.yaml"), spec);
  LocalCluster cluster(dir.path(), dir.File("r.db"));
  if (!cluster.ok()) return {};
  auto submit = cluster.Cli("submit " + dir.File("s.yaml"));
  EXPECT_EQ(submit.exit_code, 0) << submit.err;
  const std::string id = submit.out.substr(0, submit.out.find('\n'));
  cluster.StartWorkers(1);
  auto watch = cluster.Cli("watch " + id);
  EXPECT_EQ(watch.exit_code, 0) << watch.err;
  return {watch.err, cluster.Cli("show " + id).out};
}

TEST(StopReason, CmaesAndSweepSayWhyTheyStopped) {
  auto [watch, show] =
      RunToTheEnd(std::string("name: cm\nseed: 2\nengine: cmaes\ngenerations: 500\n") + kSpace +
                  "cmaes: {max_evaluations: 60}\n");
  const std::string cmaes = "CMA-ES: another generation would pass max_evaluations = 60 (60 done)";
  EXPECT_NE(watch.find("completed after 10 generations"), std::string::npos) << watch;
  EXPECT_NE(watch.find("stopped: " + cmaes + "\n"), std::string::npos) << watch;
  EXPECT_NE(show.find("stopped      " + cmaes + "\n"), std::string::npos) << show;

  std::tie(watch, show) =
      RunToTheEnd(std::string("name: sw\nseed: 2\nengine: sweep\ngenerations: 500\n") + kSpace +
          "sweep: {points_per_axis: [3], top_k: 1, nm_max_iterations: 10}\n");
  const std::string sweep =
      "sweep: the grid is done and every Nelder-Mead search has converged (nm_tolerance) or "
      "used nm_max_iterations";
  EXPECT_NE(watch.find("stopped: " + sweep + "\n"), std::string::npos) << watch;
  EXPECT_NE(show.find("stopped      " + sweep + "\n"), std::string::npos) << show;

  // A study that ran all its generations says that.
  std::tie(watch, show) =
      RunToTheEnd(std::string("name: ga\nseed: 2\npopulation: 6\ngenerations: 2\n") + kSpace +
                  "ga: {elite: 1}\n");
  EXPECT_NE(show.find("stopped      its 2 generations are done\n"), std::string::npos) << show;
}

}  // namespace
}  // namespace gaitforge::testing
