// Decimal parameter parsing to fixed point: accepted forms, malformed forms, overflow, and
// rounding against a double-precision reference.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "firmware/gcode_number.h"

namespace {

using gcode::number_to_fixed;
using gcode::number_valid;

int32_t parse(const char* text, uint8_t frac_bits) {
  int32_t value = -12345;
  EXPECT_TRUE(number_to_fixed(text, frac_bits, &value)) << text;
  return value;
}

bool rejects(const char* text, uint8_t frac_bits) {
  int32_t value = -12345;
  const bool ok = number_to_fixed(text, frac_bits, &value);
  return !ok && value == -12345;  // nothing written on failure
}

TEST(GcodeNumber, AcceptedForms) {
  for (const char* text : {"0", "210", "-3.5", "+1", ".25", "7.", "00012", "1.000000000"}) {
    EXPECT_TRUE(number_valid(text)) << text;
  }
  EXPECT_TRUE(number_valid("12 S3"));  // the token ends at a blank
}

TEST(GcodeNumber, MalformedForms) {
  for (const char* text : {"", " ", "-", "+", ".", "-.", "2x1", "--1", "+-1", "1e3", "1.2.3",
                           "S", "0x10", "1,5", "1-"}) {
    EXPECT_FALSE(number_valid(text)) << '"' << text << '"';
    EXPECT_TRUE(rejects(text, 16)) << text;
  }
}

TEST(GcodeNumber, Q16Values) {
  EXPECT_EQ(parse("210", 16), 210 * 65536);
  EXPECT_EQ(parse("210.5", 16), 210 * 65536 + 32768);
  EXPECT_EQ(parse("-3.25", 16), -(3 * 65536 + 16384));
  EXPECT_EQ(parse(".5", 16), 32768);
  EXPECT_EQ(parse("22.2", 16), 1454899);  // 1454899.2 rounded
  EXPECT_EQ(parse("1.08", 16), 70779);    // 70778.88 rounded
  EXPECT_EQ(parse("32767.99998", 16), 0x7FFFFFFF);
  EXPECT_EQ(parse("-0", 16), 0);
}

TEST(GcodeNumber, Q8Values) {
  EXPECT_EQ(parse("210.5", 8), 53888);
  EXPECT_EQ(parse("209.995", 8), 53759);  // 53758.72 rounded
  EXPECT_EQ(parse("127.5", 8), 127 * 256 + 128);
}

TEST(GcodeNumber, Overflow) {
  EXPECT_TRUE(rejects("32768", 16));
  EXPECT_EQ(parse("32767.99999", 16), 0x7FFFFFFF);  // 2147483647.3 rounds down: fits
  EXPECT_TRUE(rejects("32767.999999", 16));        // 2147483647.9 rounds up to 2^31
  EXPECT_TRUE(rejects("-32768", 16));        // symmetric range: |value| <= 0x7FFFFFFF
  EXPECT_TRUE(rejects("99999999999999999999", 16));
  EXPECT_TRUE(rejects("2147483648", 0));
  EXPECT_EQ(parse("2147483647", 0), 2147483647);
  EXPECT_EQ(parse("-2147483647", 0), -2147483647);
}

TEST(GcodeNumber, IntegersRejectFractions) {
  EXPECT_EQ(parse("42", 0), 42);
  EXPECT_EQ(parse("42.000", 0), 42);
  EXPECT_TRUE(rejects("42.5", 0));
  EXPECT_TRUE(rejects("0.0000001", 0));
}

// Every number with up to three decimals in -300..300, and a few long fractions, against
// round(x * 2^bits) in double precision (no ties occur: 10^-k is never an exact Q16 half step).
TEST(GcodeNumber, MatchesDoubleReference) {
  char text[32];
  for (int32_t milli = -300000; milli <= 300000; milli += 7) {
    std::snprintf(text, sizeof text, "%s%d.%03d", milli < 0 ? "-" : "", std::abs(milli) / 1000,
                  std::abs(milli) % 1000);
    for (uint8_t bits : {8, 16}) {
      const double exact = milli / 1000.0 * std::ldexp(1.0, bits);
      ASSERT_EQ(parse(text, bits), static_cast<int32_t>(std::round(exact))) << text;
    }
  }
  EXPECT_EQ(parse("0.1234567890123", 16), static_cast<int32_t>(std::round(0.1234567890123 * 65536)));
  EXPECT_EQ(parse("3.14159265358979", 16), static_cast<int32_t>(std::round(3.14159265358979 * 65536)));
}

}  // namespace
