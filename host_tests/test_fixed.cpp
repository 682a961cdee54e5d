// Fixed-point helpers against exact (64-bit / double) arithmetic.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "control/fixed.h"

namespace {

TEST(Fixed, ClampAndSaturation) {
  EXPECT_EQ(fixed::clamp(5, 0, 3), 3);
  EXPECT_EQ(fixed::clamp(-5, 0, 3), 0);
  EXPECT_EQ(fixed::clamp(2, 0, 3), 2);
  EXPECT_EQ(fixed::sat_u16(-1), 0);
  EXPECT_EQ(fixed::sat_u16(65536), 65535);
  EXPECT_EQ(fixed::sat_u16(1234), 1234);
}

TEST(Fixed, SaturatingAddNeverWraps) {
  EXPECT_EQ(fixed::add_sat(INT32_MAX - 1, 5), INT32_MAX);
  EXPECT_EQ(fixed::add_sat(INT32_MIN + 1, -5), INT32_MIN);
  EXPECT_EQ(fixed::add_sat(INT32_MAX, INT32_MIN), -1);
  for (int64_t a = -3000000000LL; a <= 3000000000LL; a += 123456789) {
    for (int64_t b = -3000000000LL; b <= 3000000000LL; b += 234567891) {
      if (a < INT32_MIN || a > INT32_MAX || b < INT32_MIN || b > INT32_MAX) continue;
      const int64_t exact = std::max<int64_t>(INT32_MIN, std::min<int64_t>(INT32_MAX, a + b));
      EXPECT_EQ(fixed::add_sat(int32_t(a), int32_t(b)), exact);
    }
  }
}

TEST(Fixed, RoundingShiftRoundsToNearestHalvesUp) {
  EXPECT_EQ(fixed::shr_round(int32_t{383}, 8), 1);  // 1.496
  EXPECT_EQ(fixed::shr_round(int32_t{384}, 8), 2);  // 1.5
  EXPECT_EQ(fixed::shr_round(int32_t{-383}, 8), -1);
  EXPECT_EQ(fixed::shr_round(int32_t{-384}, 8), -1);  // -1.5 rounds up
  EXPECT_EQ(fixed::shr_round(int32_t{-385}, 8), -2);
  for (int32_t x = -100000; x <= 100000; x += 7) {
    EXPECT_EQ(fixed::shr_round(x, 4), int32_t(std::floor(x / 16.0 + 0.5))) << x;
  }
  EXPECT_EQ(fixed::shr_round(uint32_t{0xFFFF0000u}, 16), 0xFFFFu);
}

TEST(Fixed, WideningMultiplies) {
  EXPECT_EQ(fixed::mul_u16(65535, 65535), 4294836225u);
  EXPECT_EQ(fixed::mul_i16(-32768, -32768), 1073741824);
  EXPECT_EQ(fixed::mul_i16(-32768, 32767), -1073709056);
  EXPECT_EQ(fixed::mul_i16_u16(-32768, 65535), -2147450880);
}

TEST(Fixed, MulQ16IsExactFloorOverTheWholeRange) {
  const int32_t xs[] = {INT32_MIN, INT32_MIN + 1, -65537,    -65536,     -65535,        -1,       0, 1,
                        65535,     65536,         123456789, -987654321, INT32_MAX - 1, INT32_MAX};
  const uint16_t as[] = {0, 1, 2, 32767, 32768, 40000, 65534, 65535};
  for (int32_t x : xs) {
    for (uint16_t a : as) {
      const int64_t p = int64_t(x) * a;
      const int64_t floor_div = p >= 0 ? p / 65536 : -((-p + 65535) / 65536);
      EXPECT_EQ(fixed::mul_q16(x, a), floor_div) << x << " * " << a;
    }
  }
}

TEST(Fixed, MulQ16RoundIsExactRoundHalfUp) {
  const int32_t xs[] = {INT32_MIN + 32768, -65537,           -65536, -3, -1, 0, 1, 3, 65535,
                        123456789,         INT32_MAX - 65536};
  const uint16_t as[] = {0, 1, 32768, 40000, 65535};
  for (int32_t x : xs) {
    for (uint16_t a : as) {
      const int64_t p = int64_t(x) * a + 32768;
      const int64_t exact = p >= 0 ? p / 65536 : -((-p + 65535) / 65536);
      EXPECT_EQ(fixed::mul_q16_round(x, a), exact) << x << " * " << a;
    }
  }
}

TEST(Fixed, MultiplierRatioIsNearestAndAppliesExactly) {
  struct Case {
    uint32_t a, b, c;
  };
  const Case cases[] = {{1454899, 257, 65536},          // Kp 22.2 → q24 per q8
                        {897, 128 * 2056, 125u << 16},  // Ki 0.0137 at 128 ms → q30 per q8 per sample
                        {7471104, 257000, 128u << 16},  // Kd 114 at 128 ms
                        {65535, 65535, 65536},          // fraction 65535/65536·65535: carries near 1
                        {3, 1, 3}};
  for (const Case& k : cases) {
    const fixed::Multiplier m = fixed::multiplier_ratio(k.a, k.b, k.c);
    const double exact = double(k.a) * k.b / k.c;
    EXPECT_LE(std::fabs(m.whole + m.frac_q16 / 65536.0 - exact), 0.5 / 65536 + 1e-12) << k.a;
    const int32_t limit = int32_t((1L << 30) / (m.whole + 1));  // mul_round's precondition
    for (int32_t x : {-limit, -100000, -257, -1, 0, 1, 255, 76800, limit}) {
      if (x < -limit || x > limit) continue;
      const double product = x * (m.whole + m.frac_q16 / 65536.0);
      EXPECT_EQ(fixed::mul_round(x, m), int32_t(std::floor(product + 0.5))) << x;
    }
  }
}

TEST(Fixed, MulDivRoundsLikeA64BitComputation) {
  const uint32_t as[] = {0, 1, 2, 257, 65535, 65536, 1454899, 123456789, 4294967295u};
  const uint32_t bs[] = {0, 1, 3, 257, 1000, 32896, 65536, 257000, 4294967295u};
  const uint32_t cs[] = {1, 2, 3, 1000, 65536, 256000, 8388608, 2147483647u, 2147483648u};
  int checked = 0;
  for (uint32_t a : as) {
    for (uint32_t b : bs) {
      for (uint32_t c : cs) {
        const uint64_t exact = (uint64_t(a) * b + c / 2) / c;  // round half up (c odd: same)
        if (exact > 0xFFFFFFFFu) continue;
        EXPECT_EQ(fixed::mul_div_u32(a, b, c), exact) << a << "*" << b << "/" << c;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 400);
  const fixed::QuotientRemainder qr = fixed::mul_divmod_u32(4294967295u, 2147483647u, 2147483648u);
  EXPECT_EQ(qr.quotient, 4294967293u);  // (2^32−1)(2^31−1) = (2^32−3)·2^31 + 1
  EXPECT_EQ(qr.remainder, 1u);
  static_assert(fixed::mul_div_u32(7, 1, 2) == 4, "3.5 rounds up");
}

TEST(Fixed, CompileTimeConversions) {
  static_assert(fixed::from_double(22.2, 16) == 1454899, "22.2 in Q16, rounded");
  static_assert(fixed::from_double(-1.5, 8) == -384, "negative rounds away from zero");
  EXPECT_DOUBLE_EQ(fixed::to_double(-384, 8), -1.5);
}

}  // namespace
