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

}  // namespace
