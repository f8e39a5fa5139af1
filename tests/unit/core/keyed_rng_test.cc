#include "services/core/keyed_rng.h"

#include <gtest/gtest.h>

#include <set>

namespace gaitforge::core {
namespace {

TEST(KeyedRng, SameKeySameStream) {
  KeyedRng a(7, 3, 11, Purpose::kMutate), b(7, 3, 11, Purpose::kMutate);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(a.NextU64(), b.NextU64());
}

TEST(KeyedRng, EveryKeyPartChangesTheStream) {
  const uint64_t base = KeyedRng(7, 3, 11, Purpose::kMutate).NextU64();
  EXPECT_NE(base, KeyedRng(8, 3, 11, Purpose::kMutate).NextU64());
  EXPECT_NE(base, KeyedRng(7, 4, 11, Purpose::kMutate).NextU64());
  EXPECT_NE(base, KeyedRng(7, 3, 12, Purpose::kMutate).NextU64());
  EXPECT_NE(base, KeyedRng(7, 3, 11, Purpose::kSelect).NextU64());
  // Swapping generation and member must not collide either.
  EXPECT_NE(KeyedRng(7, 3, 11, Purpose::kMutate).NextU64(),
            KeyedRng(7, 11, 3, Purpose::kMutate).NextU64());
}

TEST(KeyedRng, UniformStaysInRangeAndCoversIt) {
  KeyedRng r(1, 0, 0, Purpose::kInit);
  double lo = 1, hi = 0, sum = 0;
  const int n = 100000;
  for (int i = 0; i < n; ++i) {
    const double u = r.Uniform(0.2, 2.0);
    ASSERT_GE(u, 0.2);
    ASSERT_LT(u, 2.0);
    lo = std::min(lo, u);
    hi = std::max(hi, u);
    sum += u;
  }
  EXPECT_LT(lo, 0.21);
  EXPECT_GT(hi, 1.99);
  EXPECT_NEAR(sum / n, 1.1, 0.01);  // mean of U(0.2, 2.0); sd of the mean ~0.0016
}

TEST(KeyedRng, UniformIntIsUnbiasedOverSmallRange) {
  KeyedRng r(5, 1, 2, Purpose::kCrossover);
  std::vector<int> counts(12, 0);
  const int n = 120000;
  for (int i = 0; i < n; ++i) {
    const int64_t k = r.UniformInt(1, 12);
    ASSERT_GE(k, 1);
    ASSERT_LE(k, 12);
    ++counts[k - 1];
  }
  for (int c : counts) EXPECT_NEAR(c, 10000, 400);  // 4 sigma
}

}  // namespace
}  // namespace gaitforge::core
