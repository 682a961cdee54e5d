// Fixed-point helpers against exact (64-bit / double) arithmetic.
#include "control/fixed.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

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
  EXPECT_EQ(fixed::shr_round(int32_t{383}, 8), 1);   // 1.496
  EXPECT_EQ(fixed::shr_round(int32_t{384}, 8), 2);   // 1.5
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
  const int32_t xs[] = {INT32_MIN, INT32_MIN + 1, -65537, -65536, -65535, -1, 0, 1, 65535, 65536,
                        123456789, -987654321, INT32_MAX - 1, INT32_MAX};
  const uint16_t as[] = {0, 1, 2, 32767, 32768, 40000, 65534, 65535};
  for (int32_t x : xs) {
    for (uint16_t a : as) {
      const int64_t p = int64_t(x) * a;
      const int64_t floor_div = p >= 0 ? p / 65536 : -((-p + 65535) / 65536);
      EXPECT_EQ(fixed::mul_q16(x, a), floor_div) << x << " * " << a;
    }
  }
}

TEST(Fixed, CompileTimeConversions) {
  static_assert(fixed::from_double(22.2, 16) == 1454899, "22.2 in Q16, rounded");
  static_assert(fixed::from_double(-1.5, 8) == -384, "negative rounds away from zero");
  EXPECT_DOUBLE_EQ(fixed::to_double(-384, 8), -1.5);
}

}  // namespace
