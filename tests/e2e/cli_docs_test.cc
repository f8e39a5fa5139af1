// docs/cli.md against the binaries: every flag a table documents for a binary is one its
// --help lists (the same registration the parser accepts).
#include <gtest/gtest.h>

#include <regex>
#include <sstream>

#include "tests/e2e/cluster.h"
#include "tests/support/temp_dir.h"

namespace gaitforge::testing {
namespace {

// Section "## NAME" of docs/cli.md -> the flags in the first cell of its table rows.
std::map<std::string, std::vector<std::string>> DocumentedFlags() {
  std::istringstream doc(ReadFile(std::string(GAITFORGE_SOURCE_DIR) + "/docs/cli.md"));
  std::map<std::string, std::vector<std::string>> out;
  std::string section, line;
  const std::regex flag("--[a-z][a-z0-9-]*");
  while (std::getline(doc, line)) {
    if (line.rfind("## ", 0) == 0) section = line.substr(3);
    if (line.rfind("| `--", 0) != 0) continue;
    const std::string cell = line.substr(1, line.find('|', 1) - 1);
    for (std::sregex_iterator it(cell.begin(), cell.end(), flag), end; it != end; ++it)
      out[section].push_back(it->str());
  }
  return out;
}

TEST(CliDocs, EveryDocumentedFlagIsOneTheBinaryHas) {
  const auto documented = DocumentedFlags();
  for (const char* binary :
       {"gaitforge", "gaitforge-sim", "gaitforge-coordinator", "gaitforge-worker"}) {
    ASSERT_TRUE(documented.count(binary)) << "docs/cli.md has no section '## " << binary << "'";
    auto help = RunCommand(Bin(binary) + " --help");
    EXPECT_EQ(help.exit_code, 0) << binary << "\n" << help.err;
    EXPECT_GE(documented.at(binary).size(), 8u) << binary;
    for (const auto& f : documented.at(binary))
      EXPECT_TRUE(std::regex_search(help.out, std::regex("\n  " + f + "[ \n]")))
          << binary << " --help does not list " << f << ", which docs/cli.md documents";
  }
}

TEST(CliDocs, EachCommandHasItsOwnHelpWithAnExample) {
  const std::string global = RunCommand(Bin("gaitforge") + " --help").out;
  for (const char* command : {"local", "submit", "watch", "list", "show", "hof", "history",
                              "individuals", "plot", "report", "trajectory", "diagnose",
                              "recording", "resume", "cancel", "health", "validate"}) {
    auto help = RunCommand(Bin("gaitforge") + " " + command + " --help");
    EXPECT_EQ(help.exit_code, 0) << command;
    EXPECT_EQ(help.out.rfind(std::string("usage: gaitforge ") + command, 0), 0u) << help.out;
    EXPECT_NE(help.out.find(std::string("example:\n  gaitforge")), std::string::npos)
        << help.out;
    EXPECT_NE(help.out, global) << command;
    // The command is in the list, and the list is not in the command's help.
    EXPECT_TRUE(std::regex_search(global, std::regex(std::string("\n  ") + command + " ")))
        << command;
    EXPECT_EQ(help.out.find("commands:"), std::string::npos) << command;
  }
  EXPECT_NE(RunCommand(Bin("gaitforge") + " hof --help").out.find("--generation"),
            std::string::npos);
  EXPECT_EQ(RunCommand(Bin("gaitforge") + " list --help").out.find("--generation"),
            std::string::npos);
}

TEST(CliDocs, HealthAsksTheCoordinator) {
  TempDir dir;
  LocalCluster cluster(dir.path(), dir.File("r.db"));
  ASSERT_TRUE(cluster.ok());
  auto r = cluster.Cli("health");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "SERVING\n");
  const std::string target = cluster.target();
  cluster.StopCoordinator();
  r = RunCommand(Bin("gaitforge") + " --coordinator " + target + " --timeout 2 health");
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_NE(r.err.find("gaitforge: health of " + target + ": "), std::string::npos) << r.err;
  r = RunCommand("env -u GAITFORGE_COORDINATOR " + Bin("gaitforge") + " health");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("health needs --coordinator"), std::string::npos) << r.err;
}

// The model file flag and the objective's params were both --params: the parser kept the
// second, so a model file never took effect.
TEST(CliDocs, TheSimulatorReadsTheModelFileItIsGiven) {
  TempDir dir;
  auto r = RunCommand(Bin("gaitforge-sim") + " wave --periods 1,1,1 --params " +
                      dir.File("missing.yaml"));
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_NE(r.err.find(dir.File("missing.yaml")), std::string::npos) << r.err;
  r = RunCommand(Bin("gaitforge-sim") + " calibration-eval --recordings " + dir.File("a.csv") +
                 " --error shape --metric mae --max-shift 5 --out-dir " + dir.File("o"));
  EXPECT_EQ(r.err.find("unknown flag"), std::string::npos) << r.err;
}

// No robot is assumed: a simulation names its robot, and an evaluation against recordings
// takes the one their sidecar names.
TEST(CliDocs, TheSimulatorRunsTheRobotItIsToldOrTheRecordingsOne) {
  TempDir dir;
  auto r = RunCommand(Bin("gaitforge-sim") + " trajectory --genes 2,0.6,0.2,0.25 --out " +
                      dir.File("a.csv"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--robot is required"), std::string::npos) << r.err;
  r = RunCommand(Bin("gaitforge-sim") +
                 " trajectory --robot walker --genes 2,0.4,0,0.1 "
                 "--cycles 2 --settle 0 --out " +
                 dir.File("w.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = RunCommand(Bin("gaitforge-sim") + " calibration-eval --recordings " + dir.File("w.csv"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\"valid\": true"), std::string::npos) << r.out;
  WriteFile(dir.File("w.csv.json"), "{\"robot\": \"no-such-robot\", \"command\": {}}");
  r = RunCommand(Bin("gaitforge-sim") + " calibration-eval --recordings " + dir.File("w.csv"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("w.csv.json"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("give --robot"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace gaitforge::testing
