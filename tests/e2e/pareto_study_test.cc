// End to end: multi-objective studies (engine nsga2). ZDT1 through real workers gives the
// same study with one worker or three, a front that no evaluated member dominates, near the
// problem's true front, and its figure; paper 002's speed against cost of transport on the
// Go2 (examples/go2-pareto.yaml) on a small budget.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>

#include "tests/e2e/cluster.h"
#include "tests/support/temp_dir.h"

namespace gaitforge::testing {
namespace {

const char* kZdt1 = R"(name: zdt1
seed: 11
engine: nsga2
population: 24
generations: 16
objective: {name: analytic.zdt1}
bounds:
  - {name: x0, lo: 0, hi: 1}
  - {name: x1, lo: 0, hi: 1}
  - {name: x2, lo: 0, hi: 1}
  - {name: x3, lo: 0, hi: 1}
nsga2:
  objectives:
    - {metric: f1, sense: minimize}
    - {metric: f2, sense: minimize}
)";

std::string RunZdt1(const TempDir& dir, const std::string& db, int workers) {
  const std::string id = RunClusterStudy(dir, db, kZdt1, workers);
  auto plot =
      RunCommand(Bin("gaitforge") + " --db " + db + " plot " + id + " --out " + dir.File("fig"));
  EXPECT_EQ(plot.exit_code, 0) << plot.err;
  return id;
}

// The last generation's hall of fame (the front) with each member's metric `name`.
const char* kFront =
    "WITH last AS (SELECT MAX(generation) AS g FROM hall_of_fame), "
    "m AS (SELECT generation, member, "
    "  MAX(CASE name WHEN 'f1' THEN value END) AS f1, MAX(CASE name WHEN 'f2' THEN value END) AS "
    "f2 "
    "  FROM metrics GROUP BY generation, member), "
    "front AS (SELECT m.* FROM hall_of_fame h, last, m WHERE h.generation = last.g AND "
    "  m.generation = h.origin_generation AND m.member = h.origin_member) ";

TEST(ParetoStudy, Zdt1sFrontIsTheSameWithOneOrThreeWorkersAndNoMemberDominatesIt) {
  TempDir a, b;
  const std::string db1 = a.File("one.db"), db3 = b.File("three.db");
  const std::string id = RunZdt1(a, db1, 1);
  ASSERT_FALSE(id.empty());
  ASSERT_FALSE(RunZdt1(b, db3, 3).empty());
  for (const char* q :
       {"SELECT generation, member, hex(genes), valid, fitness FROM individuals "
        "ORDER BY generation, member",
        "SELECT generation, rank, hex(genes) FROM hall_of_fame ORDER BY generation, rank",
        "SELECT hex(engine_state) FROM generations ORDER BY generation"})
    EXPECT_EQ(Rows(db1, q), Rows(db3, q)) << q;
  EXPECT_EQ(Rows(db1, "SELECT evaluations FROM studies")[0], "384|");  // 24 x 16, none carried
  const auto size = Rows(db1, std::string(kFront) + "SELECT COUNT(*) FROM front");
  EXPECT_GE(std::stoi(size[0]), 8);
  // Constrained domination over every evaluated member: none dominates a front member.
  EXPECT_EQ(Rows(db1, std::string(kFront) +
                          "SELECT COUNT(*) FROM front f, m WHERE m.f1 <= f.f1 AND m.f2 <= f.f2 "
                          "AND (m.f1 < f.f1 OR m.f2 < f.f2)")[0],
            "0|");
  // Near ZDT1's true front f2 = 1 - sqrt(f1) after 384 evaluations, and spread along it.
  const auto gap = Rows(db1, std::string(kFront) +
                                 "SELECT MAX(f2 - (1 - sqrt(f1))), "
                                 "MIN(f1), MAX(f1) FROM front");
  std::smatch m;
  const std::string row = gap[0];
  ASSERT_TRUE(std::regex_match(row, m, std::regex(R"(([-0-9.e]+)\|([-0-9.e]+)\|([-0-9.e]+)\|)")))
      << row;
  EXPECT_LT(std::stod(m[1]), 1.0) << row;
  EXPECT_LT(std::stod(m[2]), 0.2) << row;
  EXPECT_GT(std::stod(m[3]), 0.6) << row;
  EXPECT_TRUE(std::filesystem::exists(a.File("fig/" + id + "-pareto.svg")));
  EXPECT_NE(ReadFile(a.File("fig/" + id + "-pareto.json")).find("\"sense\": \"minimize\""),
            std::string::npos);
}

// Paper 002's speed against energy on a small budget: the example runs end to end through
// `gaitforge local`, its front holds valid gaits each with both metrics, no front member
// is faster and cheaper than another, and the figure is written.
TEST(ParetoStudy, TheGo2sSpeedAgainstCostOfTransportGivesAFrontAndItsFigure) {
  TempDir dir;
  std::string text = ReadFile(std::string(GAITFORGE_SOURCE_DIR) + "/examples/go2-pareto.yaml");
  text = std::regex_replace(text, std::regex(R"(population: \d+)"), "population: 8");
  text = std::regex_replace(text, std::regex(R"(generations: \d+)"), "generations: 2");
  text = std::regex_replace(text, std::regex(R"(cycles: \d+, settle)"), "cycles: 3, settle");
  const std::string id = RunLocal(dir, text, "completed after 2 generations");
  ASSERT_FALSE(id.empty());
  const std::string hof =
      RunCommand("cd " + dir.path() + " && " + Bin("gaitforge") + " hof " + id + " --json").out;
  const std::regex entry(
      R"re("electrical_cost_of_transport":([-0-9.e]+).*?"speed_m_s":([-0-9.e]+))re");
  std::vector<std::pair<double, double>> front;  // (speed, cost)
  for (auto it = std::sregex_iterator(hof.begin(), hof.end(), entry); it != std::sregex_iterator();
       ++it)
    front.emplace_back(std::stod((*it)[2]), std::stod((*it)[1]));
  ASSERT_GE(front.size(), 1u) << hof;
  for (const auto& [speed, cost] : front) {
    EXPECT_GT(speed, 0);
    EXPECT_GT(cost, 0);
    for (const auto& [s2, c2] : front)
      EXPECT_FALSE(s2 >= speed && c2 <= cost && (s2 > speed || c2 < cost)) << hof;
  }
  // Best speed first (the first objective).
  for (size_t i = 1; i < front.size(); ++i) EXPECT_GE(front[i - 1].first, front[i].first);
  EXPECT_GT(ReadFile(dir.File("runs/plots/" + id + "-pareto.svg")).size(), 1000u);
}

}  // namespace
}  // namespace gaitforge::testing
