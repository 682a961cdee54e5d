// Integer-only logarithms for the end-of-tune arithmetic of the autotune (control/autotune.cpp):
// the relay formulas need ln of ratios. No float, no 64-bit, no loop over result bits: a 64-entry
// table with linear interpolation, so one call is one 16×16 multiply plus the normalising shifts
// (≈ 250 AVR cycles for log2_q16, twice that for ln_ratio_q16: fits one control step).
// host_tests/test_fixed_math.cpp reports the worst error against <cmath> over the domain.
#pragma once

#include <stdint.h>

namespace fixed_math {

constexpr uint16_t kLn2Q16 = 45426;  // ln 2 · 2^16

// log2(1 + i/64) · 2^16, i = 0..63 (i = 64 would be 2^16). 128 bytes.
constexpr uint16_t kLog2Table[64] = {
    0,     1466,  2909,  4331,  5732,  7112,  8473,  9814,  11136, 12440, 13727, 14996, 16248,
    17484, 18704, 19909, 21098, 22272, 23433, 24579, 25711, 26830, 27936, 29029, 30109, 31178,
    32234, 33279, 34312, 35334, 36346, 37346, 38336, 39316, 40286, 41246, 42196, 43137, 44068,
    44990, 45904, 46809, 47705, 48593, 49472, 50344, 51207, 52063, 52911, 53751, 54584, 55410,
    56229, 57040, 57845, 58643, 59434, 60219, 60997, 61769, 62534, 63294, 64047, 64794};

// log2(x) · 2^16 for x ≥ 1 (0 for x = 0, which has no logarithm: callers exclude it).
// x normalised to 1.f · 2^31 (byte shifts first: cheap on AVR); 6 bits of f index the table,
// the next 16 interpolate (the chord under a concave curve: worst error 3.4 units of 2^-16).
inline int32_t log2_q16(uint32_t x) {
  if (x == 0) return 0;
  int8_t e = 31;
  while (!(x & 0xFF000000u)) { x <<= 8; e = static_cast<int8_t>(e - 8); }
  while (!(x & 0x80000000u)) { x <<= 1; --e; }
  const uint8_t i = static_cast<uint8_t>((x >> 25) & 63u);
  const uint16_t t = static_cast<uint16_t>(x >> 9);
  const uint16_t lo = kLog2Table[i];
  const uint16_t step = static_cast<uint16_t>((i == 63 ? 65536u : kLog2Table[i + 1]) - lo);  // ≤ 1466
  // step · t ≤ 1466 · 65535 < 2^27.
  return static_cast<int32_t>(e) * 65536 + lo + static_cast<int32_t>((static_cast<uint32_t>(step) * t + 0x8000u) >> 16);
}

// A base-2 logarithm (Q16) as a natural one: d · ln 2. |d| ≤ 32·2^16 = 2^21, so d · 45426 needs
// 37 bits: split into the whole and fraction parts of d, each product < 2^32.
inline int32_t ln_from_log2_q16(int32_t d) {
  const bool neg = d < 0;
  const uint32_t a = static_cast<uint32_t>(neg ? -d : d);
  const uint32_t r = (a >> 16) * kLn2Q16 + (((a & 0xFFFFu) * kLn2Q16 + 0x8000u) >> 16);
  return neg ? -static_cast<int32_t>(r) : static_cast<int32_t>(r);
}

// ln(num / den) · 2^16 for num, den ≥ 1: (log2 num − log2 den) · ln 2.
inline int32_t ln_ratio_q16(uint32_t num, uint32_t den) { return ln_from_log2_q16(log2_q16(num) - log2_q16(den)); }

}  // namespace fixed_math
