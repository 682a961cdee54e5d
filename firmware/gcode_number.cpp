#include "firmware/gcode_number.h"

namespace gcode {
namespace {

// A valid token split into sign, integer digits and fraction digits.
struct Parts {
  bool negative = false;
  const char* int_begin = nullptr;
  const char* frac_begin = nullptr;  // just after the '.', or int_end when there is none
  const char* end = nullptr;         // the blank or NUL ending the token
};

bool split(const char* s, Parts* parts) {
  if (*s == '+' || *s == '-') parts->negative = (*s++ == '-');
  parts->int_begin = s;
  while (is_digit(*s)) ++s;
  const bool int_digits = s != parts->int_begin;
  if (*s == '.') ++s;
  parts->frac_begin = s;
  while (is_digit(*s)) ++s;
  parts->end = s;
  return (int_digits || s != parts->frac_begin) && is_blank(*s);
}

}  // namespace

bool number_valid(const char* s) {
  Parts parts;
  return split(s, &parts);
}

bool number_to_fixed(const char* s, uint8_t frac_bits, int32_t* value) {
  Parts parts;
  if (!split(s, &parts)) return false;
  constexpr uint32_t kMax = 0x7FFFFFFFu;
  const uint32_t whole_limit = kMax >> frac_bits;
  uint32_t whole = 0;
  for (const char* p = parts.int_begin; is_digit(*p); ++p) {
    const uint32_t digit = static_cast<uint32_t>(*p - '0');
    if (whole > (whole_limit - digit) / 10u) return false;  // checked before it can wrap
    whole = whole * 10u + digit;
  }
  // Fraction by Horner's rule from the last digit, in Q24 so truncation stays far below the
  // final rounding step (at most Q16).
  uint32_t frac_q24 = 0;
  bool frac_nonzero = false;
  for (const char* p = parts.end; p != parts.frac_begin;) {
    const uint32_t digit = static_cast<uint32_t>(*--p - '0');
    frac_nonzero |= digit != 0;
    frac_q24 = (frac_q24 + (digit << 24)) / 10u;
  }
  if (frac_bits == 0 && frac_nonzero) return false;
  const uint8_t drop = static_cast<uint8_t>(24u - frac_bits);
  const uint32_t frac = (frac_q24 + (1ul << (drop - 1u))) >> drop;  // may round up to 1.0
  const uint32_t magnitude = (whole << frac_bits) + frac;
  if (magnitude > kMax) return false;
  *value = parts.negative ? -static_cast<int32_t>(magnitude) : static_cast<int32_t>(magnitude);
  return true;
}

}  // namespace gcode
