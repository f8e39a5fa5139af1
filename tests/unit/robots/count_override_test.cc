// Another resolution of a robot (robots/count_override.h): one count set in the
// descriptor's text, checked by its parser, errors naming the count and the line.
#include "robots/count_override.h"

#include <string>

#include "gtest/gtest.h"
#include "robots/descriptor_parser.h"
#include "robots/registry.h"

namespace gaitforge::robots {
namespace {

TEST(WithCount, SetsOneCountAndLeavesTheRestOfTheTextAlone) {
  const std::string text(BuiltinText("continuum_arm"));
  auto ten = WithCount(text, "lumps", 10, "arm.yaml");
  ASSERT_TRUE(ten.ok()) << ten.status();
  EXPECT_EQ(ten->size(), text.size() + 1);  // "5" became "10"; nothing else moved
  auto d = ParseDescriptor(*ten, "arm.yaml");
  ASSERT_TRUE(d.ok()) << d.status();
  EXPECT_EQ(d->bodies.size(), 10u);
  EXPECT_EQ(d->counts[0].value, 10);
  // Back to the paper's five: the built-in text again, byte for byte.
  EXPECT_EQ(*WithCount(*ten, "lumps", 5, "arm.yaml"), text);
}

TEST(WithCount, SaysWhatIsWrong) {
  const std::string text(BuiltinText("continuum_arm"));
  const auto missing = WithCount(text, "disks", 10, "arm.yaml");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.status().message(), "arm.yaml: no count 'disks' (its counts: lumps)");
  const auto none = WithCount(BuiltinText("caterpillar"), "lumps", 10, "caterpillar");
  EXPECT_EQ(none.status().message(), "caterpillar: no count 'lumps' (its counts: none)");
  const auto outside = WithCount(text, "lumps", 41, "arm.yaml");
  ASSERT_FALSE(outside.ok());
  EXPECT_NE(outside.status().message().find("arm.yaml:23:18: counts.lumps.value: 41 is outside "
                                            "its range [2, 40]"),
            std::string::npos)
      << outside.status().message();
}

}  // namespace
}  // namespace gaitforge::robots
