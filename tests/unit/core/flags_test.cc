#include "services/core/flags.h"

#include <gtest/gtest.h>

namespace gaitforge::core {
namespace {

void AddParamsTwice() {
  std::string model;
  std::string objective;
  Flags flags("t [flags]", "test");
  flags.Add("params", &model, "model file");
  flags.Add("params", &objective, "objective params");
}

// gaitforge-sim once had two --params: the parser set only the second.
TEST(FlagsDeathTest, ANameRegisteredTwiceAborts) {
  EXPECT_DEATH(AddParamsTwice(), "flag --params registered twice");
}

TEST(Flags, HelpForACommandListsOnlyItsFlags) {
  std::string a, b;
  Flags flags("t [flags]", "test");
  flags.Add("alpha", &a, "first");
  flags.Add("beta", &b, "second");
  const std::string help = flags.Help("t sub", "a part", {"beta"});
  EXPECT_EQ(help.rfind("usage: t sub\n\na part\n\nflags:\n", 0), 0u) << help;
  EXPECT_NE(help.find("--beta"), std::string::npos);
  EXPECT_EQ(help.find("--alpha"), std::string::npos);
}

}  // namespace
}  // namespace gaitforge::core
