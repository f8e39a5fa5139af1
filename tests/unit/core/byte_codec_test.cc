#include "services/core/byte_codec.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

namespace gaitforge::core {
namespace {

TEST(ByteCodec, RoundTripIsBitExact) {
  ByteWriter w;
  w.U32(0xdeadbeef);
  w.U64(~0ULL);
  w.F64(-0.0);
  w.F64(std::numeric_limits<double>::denorm_min());
  w.Str("hello");
  w.F64s({1.0 / 3.0, M_PI});
  ByteReader r(w.data());
  EXPECT_EQ(r.U32(), 0xdeadbeefu);
  EXPECT_EQ(r.U64(), ~0ULL);
  const double z = r.F64();
  EXPECT_TRUE(std::signbit(z));
  EXPECT_EQ(r.F64(), std::numeric_limits<double>::denorm_min());
  EXPECT_EQ(r.Str(), "hello");
  const auto v = r.F64s();
  ASSERT_EQ(v.size(), 2u);
  EXPECT_EQ(v[0], 1.0 / 3.0);
  EXPECT_TRUE(r.status("t").ok());
}

TEST(ByteCodec, TruncatedInputIsAnErrorNotACrash) {
  ByteWriter w;
  w.F64s({1, 2, 3});
  std::string cut = w.data().substr(0, 12);
  ByteReader r(cut);
  r.F64s();
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.status("state").code(), absl::StatusCode::kDataLoss);
}

}  // namespace
}  // namespace gaitforge::core
