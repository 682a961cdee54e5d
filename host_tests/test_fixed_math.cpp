// control/fixed_math.h against <cmath>: the worst error over each function's domain, printed
// and bounded.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "control/fixed_math.h"

namespace {

TEST(FixedMath, Log2WorstErrorOverUint32) {
  double worst = 0;
  uint32_t at = 0;
  for (uint64_t x = 1; x <= 0xFFFFFFFFull; x = x < 70000 ? x + 1 : x + x / 977 + 1) {
    const double err = std::fabs(fixed_math::log2_q16(static_cast<uint32_t>(x)) / 65536.0 - std::log2(static_cast<double>(x)));
    if (err > worst) { worst = err; at = static_cast<uint32_t>(x); }
  }
  std::printf("log2_q16: worst |error| %.2e (%.2f units of 2^-16) at x = %u\n", worst, worst * 65536, at);
  EXPECT_LT(worst * 65536, 5.0);
}

TEST(FixedMath, LnRatioWorstError) {
  double worst = 0;
  for (uint32_t num = 1; num < 2000000; num = num * 5 / 4 + 1) {
    for (uint32_t den = 1; den < 2000000; den = den * 4 / 3 + 1) {
      const double err = std::fabs(fixed_math::ln_ratio_q16(num, den) / 65536.0 - std::log(static_cast<double>(num) / den));
      if (err > worst) worst = err;
    }
  }
  std::printf("ln_ratio_q16: worst |error| %.2e (%.2f units of 2^-16)\n", worst, worst * 65536);
  EXPECT_LT(worst * 65536, 6.0);
}

// ⌊√x⌋ exact: every perfect square and its neighbours up to 2^32 − 1, and a geometric sweep.
TEST(FixedMath, IsqrtIsTheFloorOfTheSquareRoot) {
  for (uint64_t r = 0; r <= 65535; ++r) {
    const uint64_t sq = r * r;
    ASSERT_EQ(fixed_math::isqrt_u32(static_cast<uint32_t>(sq)), r);
    if (sq > 0) {
      ASSERT_EQ(fixed_math::isqrt_u32(static_cast<uint32_t>(sq - 1)), r - 1);
    }
    const uint64_t next = (r + 1) * (r + 1) - 1;  // the largest x with ⌊√x⌋ = r
    ASSERT_EQ(fixed_math::isqrt_u32(static_cast<uint32_t>(next > 0xFFFFFFFFull ? 0xFFFFFFFFull : next)), r);
  }
  for (uint64_t x = 1; x <= 0xFFFFFFFFull; x += x / 1013 + 1) {
    const uint64_t r = fixed_math::isqrt_u32(static_cast<uint32_t>(x));
    ASSERT_LE(r * r, x);
    ASSERT_GT((r + 1) * (r + 1), x);
  }
}

}  // namespace
