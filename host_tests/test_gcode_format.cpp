// Number formatting of the G-code replies (no printf in the firmware), checked against exact
// text and against a double-precision reference.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "firmware/gcode_number.h"
#include "host_tests/gcode_fakes.h"

namespace {

using gcode_test::StringOutput;

std::string fixed(int32_t value, uint8_t frac_bits, uint8_t decimals) {
  StringOutput out;
  out.write_fixed(value, frac_bits, decimals);
  return out.text;
}

std::string q8(int32_t value_q8) {
  StringOutput out;
  out.write_q8(value_q8);
  return out.text;
}

TEST(GcodeFormat, Integers) {
  StringOutput out;
  out.write_uint(0);
  out.write_char(' ');
  out.write_uint(4294967295u);
  out.write_char(' ');
  out.write_int(-2147483647 - 1);
  out.write_char(' ');
  out.write_int(-7);
  out.write_char(' ');
  out.write_int(120);
  EXPECT_EQ(out.text, "0 4294967295 -2147483648 -7 120");
}

TEST(GcodeFormat, TemperatureTwoDecimals) {
  EXPECT_EQ(q8(210 * 256), "210.00");
  EXPECT_EQ(q8(0), "0.00");
  EXPECT_EQ(q8(210 * 256 + 128), "210.50");
  EXPECT_EQ(q8(25 * 256 + 64), "25.25");
  EXPECT_EQ(q8(1), "0.00");       // 0.0039
  EXPECT_EQ(q8(2), "0.01");       // 0.0078 rounds up
  EXPECT_EQ(q8(1000 * 256), "1000.00");
}

TEST(GcodeFormat, RoundsUpIntoTheNextDegree) {
  // 53759 / 256 = 209.99609 must print 210.00, not 209.100 or 209.00.
  EXPECT_EQ(q8(53759), "210.00");
  EXPECT_EQ(q8(53758), "209.99");  // 209.99219
  EXPECT_EQ(q8(-53759), "-210.00");
}

TEST(GcodeFormat, NegativeTemperatures) {
  EXPECT_EQ(q8(-10 * 256), "-10.00");
  EXPECT_EQ(q8(-256 - 64), "-1.25");
  EXPECT_EQ(q8(-64), "-0.25");
  EXPECT_EQ(q8(-1), "0.00");  // -0.0039: no "-0.00"
  EXPECT_EQ(q8(-2), "-0.01");
}

TEST(GcodeFormat, Q16Gains) {
  StringOutput out;
  out.write_q16(1454899);  // 22.2
  out.write_char(' ');
  out.write_q16(70779);    // 1.08
  out.write_char(' ');
  out.write_q16(0x7FFFFFFF);
  out.write_char(' ');
  out.write_q16(596);      // 0.0091 (a tuned Ki): 0.01 would read back 10 % larger
  EXPECT_EQ(out.text, "22.20 1.08 32767.99998 0.0091");
}

// M503 replays M301 and M307 exactly: every Q16 fraction (and Q8 value) prints with the fewest decimals (2..5) that
// number_to_fixed reads back as the same value, and values typed with two decimals print as typed.
TEST(GcodeFormat, Q16GainsReadBackExactly) {
  int mismatches = 0;
  for (int32_t frac = 0; frac < 65536; ++frac) {
    for (const int32_t whole : {0, 7, 32767}) {
      const int32_t value = whole * 65536 + frac;
      StringOutput out;
      out.write_q16(value);
      int32_t parsed = -1;
      const bool ok = gcode::number_to_fixed(out.text.c_str(), 16, &parsed);
      if (!ok || parsed != value) {
        ++mismatches;
        ADD_FAILURE() << value << " printed " << out.text << ", read back " << parsed;
      }
      const std::size_t decimals = out.text.size() - out.text.find('.') - 1;
      const bool two_do = std::lround(std::round(frac * 100.0 / 65536.0) * 65536.0 / 100.0) == frac;
      if (two_do && decimals != 2) ADD_FAILURE() << out.text << ": two decimals read back";
      if (mismatches > 5) return;
    }
  }
  for (int32_t value = 0; value < 921600; value += 7) {  // Q8 (M307's range): 2 or 3 decimals
    StringOutput out;
    out.write_exact(value, 8);
    int32_t parsed = -1;
    if (!gcode::number_to_fixed(out.text.c_str(), 8, &parsed) || parsed != value) {
      ADD_FAILURE() << value << " printed " << out.text << ", read back " << parsed;
      return;
    }
  }
  StringOutput typed;
  int32_t q = 0;
  ASSERT_TRUE(gcode::number_to_fixed("0.15", 16, &q));
  typed.write_q16(q);
  EXPECT_EQ(typed.text, "0.15");
}

TEST(GcodeFormat, DecimalsAndFractionBits) {
  EXPECT_EQ(fixed(275 * 256, 8, 0), "275");
  EXPECT_EQ(fixed(3 * 65536 + 32768, 16, 0), "4");   // 3.5 rounds half away from zero
  EXPECT_EQ(fixed(-(3 * 65536 + 32768), 16, 0), "-4");
  EXPECT_EQ(fixed(65536 / 3, 16, 4), "0.3333");
  EXPECT_EQ(fixed(1234, 0, 2), "1234.00");
  EXPECT_EQ(fixed(-2147483647 - 1, 16, 4), "-32768.0000");
  EXPECT_EQ(fixed(65536 / 3, 16, 5), "0.33333");
  EXPECT_EQ(fixed(65535, 16, 5), "0.99998");  // 0.9999847
  EXPECT_EQ(fixed(65536 - 1, 16, 4), "1.0000");
}

// Every Q8 temperature from -50 to 400 °C against printf's correctly rounded output. The only
// allowed difference: exact ties (x.xx5), which printf rounds to even and we round away from zero.
TEST(GcodeFormat, MatchesDoubleReferenceForAllTemperatures) {
  int mismatches = 0;
  for (int32_t value = -50 * 256; value <= 400 * 256; ++value) {
    const double exact = value / 256.0;
    const double hundredths = std::round(std::fabs(exact) * 100.0);  // halves away from zero
    char expected[32];
    std::snprintf(expected, sizeof expected, "%s%.0f.%02.0f", (exact < 0 && hundredths != 0) ? "-" : "",
                  std::floor(hundredths / 100.0), std::fmod(hundredths, 100.0));
    if (q8(value) != expected) {
      ++mismatches;
      ADD_FAILURE() << value << " printed " << q8(value) << ", expected " << expected;
      if (mismatches > 5) break;
    }
  }
  EXPECT_EQ(mismatches, 0);
}

}  // namespace
