// Integer-only logarithms for the end-of-tune arithmetic of the autotune (control/autotune.cpp):
// the relay formulas need ln of ratios. No float, no 64-bit, no loop over result bits: a 64-entry
// table with linear interpolation, so one call is one 16×16 multiply plus the normalising shifts
// (≈ 250 AVR cycles for log2_q16, twice that for ln_ratio_q16: fits one control step).
// host_tests/test_fixed_math.cpp reports the worst error against <cmath> over the domain.
//
// Second part (below, `Scaled`): numbers as a 30-bit mantissa with a binary exponent, for
// set-up arithmetic whose values span many decades (the on-board state-feedback design,
// control/state_feedback_autodesign.cpp: 1 − e^(−h/T) down to 1e-5 needed to 15 significant
// bits, gains up to 1e3). Integer-only; implemented in fixed_math.cpp (not inline: flash).
#pragma once

#include <stdint.h>

namespace fixed_math {

constexpr uint16_t kLn2Q16 = 45426;  // ln 2 · 2^16

// log2(1 + i/64) · 2^16, i = 0..63 (i = 64 would be 2^16). 128 bytes, read through
// log2_table() below: the firmware keeps its copy in flash (firmware/log2_table_flash.cpp),
// host builds read this one (control/log2_table.cpp).
struct Log2Table {
  uint16_t q16[64];
};
constexpr Log2Table kLog2Table{{
    0,     1466,  2909,  4331,  5732,  7112,  8473,  9814,  11136, 12440, 13727, 14996, 16248,
    17484, 18704, 19909, 21098, 22272, 23433, 24579, 25711, 26830, 27936, 29029, 30109, 31178,
    32234, 33279, 34312, 35334, 36346, 37346, 38336, 39316, 40286, 41246, 42196, 43137, 44068,
    44990, 45904, 46809, 47705, 48593, 49472, 50344, 51207, 52063, 52911, 53751, 54584, 55410,
    56229, 57040, 57845, 58643, 59434, 60219, 60997, 61769, 62534, 63294, 64047, 64794}};

// kLog2Table.q16[i], i = 0..63, from where the build keeps the table.
uint16_t log2_table(uint8_t i);

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
  const uint16_t lo = log2_table(i);
  const uint16_t step = static_cast<uint16_t>((i == 63 ? 65536u : log2_table(static_cast<uint8_t>(i + 1))) - lo);  // ≤ 1466
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

// ⌊√x⌋ (bit by bit: 16 rounds of a compare and shifts, no multiply).
uint16_t isqrt_u32(uint32_t x);

// ln(num / den) · 2^16 for num, den ≥ 1: (log2 num − log2 den) · ln 2.
inline int32_t ln_ratio_q16(uint32_t num, uint32_t den) { return ln_from_log2_q16(log2_q16(num) - log2_q16(den)); }

// ---------------------------------------------------------------------------------------------
// Scaled: value = m · 2^e with 2^29 ≤ |m| < 2^30 (normalised), or m = 0 (then e = 0). About 29
// significant bits at any magnitude between 2^-16000 and 2^16000; results outside saturate (large)
// or flush to 0 (small). Relative error ≤ 2^-27 for mul (it drops the product's low bits), ≤ 2^-29
// for div, ≤ 2^-28 of the larger operand for add/sub (what cancels is lost, as in any format).
// All products are 16×16 → 32-bit,
// divisions are restoring shift-subtract loops: no 64-bit arithmetic, no library division.
// Set-up code only (mul ~150, div ~700 AVR cycles; see control/state_feedback_autodesign.cpp).
struct Scaled {
  int32_t m;
  int16_t e;
};

// v · 2^e, normalised.
Scaled scaled(int32_t v, int16_t e = 0);
Scaled add(Scaled a, Scaled b);
Scaled sub(Scaled a, Scaled b);
Scaled mul(Scaled a, Scaled b);
Scaled div(Scaled a, Scaled b);  // b = 0 gives 0 (callers exclude it)
inline Scaled neg(Scaled a) { return Scaled{-a.m, a.e}; }
// a · 2^n (small n: the exponent range is not re-checked).
inline Scaled ldexp(Scaled a, int16_t n) { return a.m == 0 ? a : Scaled{a.m, static_cast<int16_t>(a.e + n)}; }
inline bool is_negative(Scaled a) { return a.m < 0; }
bool less(Scaled a, Scaled b);
inline Scaled min(Scaled a, Scaled b) { return less(b, a) ? b : a; }

// round(a · 2^s), halves away from zero (as the host's quantiser), saturated to ±(2^31 − 1).
int32_t round_scaled(Scaled a, int16_t s);

// e^(−x) for x ≥ 0 (x < 0 is taken as 0), relative error ≤ (1 + x)·2^-26 (host test: the
// squarings that undo the range reduction double it each). complement: 1 − e^(−x) instead, with
// *relative* precision also for small x (≤ 2^-25): Φ − 1 of a slow pole sampled fast (e^(−x)
// itself would leave only its absolute error there).
Scaled exp_neg(Scaled x, bool complement = false);
inline Scaled one_minus_exp_neg(Scaled x) { return exp_neg(x, true); }
// ln x for x > 0 (x ≤ 0 gives 0): absolute error ≤ 2^-25·(1 + |ln x|) (host test). For the pole
// rule's ln(K/(K − 185 °C)).
Scaled ln(Scaled x);

}  // namespace fixed_math
