// `gaitforge validate` end to end (real CLI, coordinator, worker processes, SQLite): a robust
// study's hall of fame evaluated again over a fresh ensemble. With nothing random in the
// ensemble the validation repeats the study's predictions bit for bit (the same gait, model
// and objective reach the workers); with sampled parameters it draws new members, gives the
// same figures with one worker or two, and is stored as a study of its own.
#include <gtest/gtest.h>

#include <string>

#include "gmock/gmock.h"
#include "google/protobuf/struct.pb.h"
#include "google/protobuf/util/json_util.h"
#include "tests/e2e/cluster.h"
#include "tests/support/temp_dir.h"

namespace gaitforge::testing {
namespace {

using google::protobuf::Struct;
using google::protobuf::Value;
using ::testing::HasSubstr;

const Value& At(const Struct& s, const std::string& k) { return s.fields().at(k); }

std::string Spec(const std::string& name, const std::string& parameters) {
  return "name: " + name + "\nseed: 5\npopulation: 4\ngenerations: 2\n"
         "objective:\n  name: caterpillar.distance\n  params: {cycles: 1, settle_cycles: 0}\n"
         "  robust:\n    numerics: [\"\"]\n" + parameters + "    statistic: mean\n"
         "ga:\n  elite: 2\n";
}

// Runs the study in `file` and returns its id.
std::string Study(const std::string& cli, const std::string& file) {
  auto r = RunCommand(cli + " local " + file + " --workers 1 --out ''");  // no figures
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return WaitForGenerations(cli, 2);
}

Struct Validate(const std::string& cli, const std::string& id, const std::string& flags) {
  auto r = RunCommand(cli + " validate " + id + " --json " + flags);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  Struct out;
  EXPECT_TRUE(google::protobuf::util::JsonStringToMessage(r.out, &out).ok()) << r.out;
  return out;
}

TEST(Validate, RepeatsAFixedEnsembleExactlyAndDrawsAFreshOneDeterministically) {
  TempDir dir;
  WriteFile(dir.File("fixed.yaml"), Spec("fixed", ""));
  WriteFile(dir.File("sampled.yaml"),
            Spec("sampled", "    parameters:\n      - {name: actuators.force_n, lo: 7, hi: 10}\n"));
  const std::string cd = "cd " + dir.path() + " && " + Bin("gaitforge") + " --dashboard off --db ";
  const std::string fixed = Study(cd + "fixed.db", "fixed.yaml");
  const Struct same = Validate(cd + "fixed.db", fixed, "--members 2 --top 2 --workers 1");
  const auto& gaits = At(same, "gaits").list_value().values();
  ASSERT_EQ(gaits.size(), 2);
  for (const Value& g : gaits) {
    const Struct& s = g.struct_value();
    ASSERT_TRUE(At(s, "valid").bool_value()) << At(s, "reason").string_value();
    EXPECT_EQ(At(At(s, "validated").struct_value(), "mean").number_value(),
              At(s, "predicted").number_value());
    EXPECT_EQ(At(At(s, "validated").struct_value(), "sd").number_value(), 0.0);
  }

  const std::string sampled = Study(cd + "sampled.db", "sampled.yaml");
  const Struct one = Validate(cd + "sampled.db", sampled, "--members 3 --workers 1");
  const Struct two = Validate(cd + "sampled.db", sampled, "--members 3 --workers 2");
  EXPECT_EQ(At(one, "seed").number_value(), 6);  // the study's ensemble seed + 1
  const auto& a = At(one, "gaits").list_value().values();
  const auto& b = At(two, "gaits").list_value().values();
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GE(a.size(), 1);
  int moved = 0;
  for (int i = 0; i < a.size(); ++i) {
    const Struct& x = a[i].struct_value();
    const double mean = At(At(x, "validated").struct_value(), "mean").number_value();
    EXPECT_EQ(mean, At(At(b[i].struct_value(), "validated").struct_value(), "mean").number_value());
    moved += mean != At(x, "predicted").number_value();
  }
  EXPECT_GE(moved, 1);  // new force samples
  // Stored beside the study, as a study of its own.
  EXPECT_THAT(RunCommand(cd + "sampled.db list").out, HasSubstr("sampled-validation-"));
}

TEST(Validate, RefusesTheStudysOwnSeedAndABadGaitsFileBeforeRunningAnything) {
  TempDir dir;
  WriteFile(dir.File("s.yaml"), Spec("s", ""));
  const std::string cli = "cd " + dir.path() + " && " + Bin("gaitforge") + " --dashboard off --db s.db";
  const std::string id = Study(cli, "s.yaml");
  auto own = RunCommand(cli + " validate " + id + " --ensemble-seed 5");
  EXPECT_EQ(own.exit_code, 2);
  EXPECT_THAT(own.err, HasSubstr("validate: seed 5 is the study's own ensemble seed"));
  WriteFile(dir.File("gaits.txt"), "# two genes only\n0.1 0.2\n");
  auto bad = RunCommand(cli + " validate " + id + " --gaits gaits.txt");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_THAT(bad.err, HasSubstr("gaits.txt:2: 2 genes; the study's space has 13"));
  auto unknown = RunCommand(cli + " validate no-such-study");
  EXPECT_EQ(unknown.exit_code, 3);
}

}  // namespace
}  // namespace gaitforge::testing
