// Integer-only logarithm and exponential for the set-up and end-of-tune arithmetic of the
// autotune (control/autotune.cpp): the relay formulas need ln of ratios and e^(−L/T). No float,
// no 64-bit: 32-bit products of 16-bit mantissas only. Each call is a loop of 16 small multiplies
// (a few hundred AVR cycles): not for the per-period path, but cheap enough for a chunk per step.
// host_tests/test_fixed_math.cpp reports the worst error against <cmath> over the domain.
//
// Second part (below, `Scaled`): numbers as a 30-bit mantissa with a binary exponent, for
// set-up arithmetic whose values span many decades (the on-board state-feedback design,
// control/state_feedback_autodesign.cpp: 1 − e^(−h/T) down to 1e-5 needed to 15 significant
// bits, gains up to 1e3). Integer-only; implemented in fixed_math.cpp (not inline: flash).
#pragma once

#include <stdint.h>

namespace fixed_math {

constexpr uint16_t kLn2Q16 = 45426;    // ln 2 · 2^16
constexpr uint32_t kLog2eQ16 = 94548;  // log2 e · 2^16

// log2(x) · 2^16 for x ≥ 1 (0 for x = 0, which has no logarithm: callers exclude it).
// Integer part = index of the top bit; fraction bit by bit by squaring the mantissa m ∈ [1, 2)
// held in Q15 (m² < 2^32). Worst error 4.3 units of 2^-16 (x ≥ 2^16 loses its low bits; test).
inline int32_t log2_q16(uint32_t x) {
  if (x == 0) return 0;
  int32_t result = 0;
  // Normalise to m ∈ [2^15, 2^16): m = x · 2^(15 − e).
  int8_t e = 0;
  uint32_t m = x;
  while (m >= (uint32_t{1} << 16)) { m >>= 1; ++e; }
  while (m < (uint32_t{1} << 15)) { m <<= 1; --e; }
  // The shift above truncated low bits of x when e > 15; fine for 15-bit mantissa precision.
  result = static_cast<int32_t>(e + 15) * 65536;  // x = m·2^e, log2 m ∈ [15, 16)
  for (uint8_t bit = 0; bit < 16; ++bit) {
    // m < 2^16 → m² < 2^32 (a 16×16 multiply on AVR); result in [2^15, 2^17).
    m = (static_cast<uint32_t>(static_cast<uint16_t>(m)) * static_cast<uint16_t>(m) + (uint32_t{1} << 14)) >> 15;
    if (m >= (uint32_t{1} << 16)) {
      m = (m + 1) >> 1;
      result += int32_t{1} << (15 - bit);
    }
  }
  return result;
}

// ln(num / den) · 2^16 for num, den ≥ 1: (log2 num − log2 den) · ln 2. |d| ≤ 32·2^16 = 2^21, so
// d · 45426 needs 37 bits: split into the whole and fraction parts of d, each product < 2^32.
inline int32_t ln_ratio_q16(uint32_t num, uint32_t den) {
  const int32_t d = log2_q16(num) - log2_q16(den);  // |d| ≤ 32 · 2^16 = 2^21
  const bool neg = d < 0;
  const uint32_t a = static_cast<uint32_t>(neg ? -d : d);
  // a · 45426 / 2^16 = (a >> 16)·45426 + ((a & 0xFFFF)·45426 + 2^15) >> 16, each product < 2^32.
  const uint32_t r = (a >> 16) * kLn2Q16 + (((a & 0xFFFFu) * kLn2Q16 + 0x8000u) >> 16);
  return neg ? -static_cast<int32_t>(r) : static_cast<int32_t>(r);
}

// e^(−x) · 2^16 for x_q16 ≥ 0 (x in Q16), rounded; 0 once it is below 2^-16·½ (x > 11.1).
// e^(−x) = 2^(−y), y = x·log2 e: whole part of y a shift, fraction bit by bit from the table
// 2^(−2^−i) (Q16). Worst error 2.9 units of 2^-16 (see the test).
inline uint32_t exp_neg_q16(uint32_t x_q16) {
  static constexpr uint16_t kHalvings[16] = {46341, 55109, 60097, 62757, 64132, 64830, 65182, 65359,
                                             65447, 65492, 65514, 65525, 65530, 65533, 65535, 65535};
  if (x_q16 >= (uint32_t{12} << 16)) return 0;
  // y = x · log2 e in Q16: x < 12·2^16 < 2^20, 94548 < 2^17 → split to keep 32 bits.
  const uint32_t y = (x_q16 >> 8) * kLog2eQ16 / 256 + ((x_q16 & 0xFFu) * kLog2eQ16 + 0x8000u) / 65536;
  const uint32_t whole = y >> 16;
  const uint32_t frac = y & 0xFFFFu;
  uint32_t acc = 65536;  // Q16, ≤ 2^16 · 65535 / 2^16 after each multiply: products < 2^32
  for (uint8_t i = 0; i < 16; ++i) {
    if (frac & (uint32_t{0x8000} >> i)) acc = (acc * kHalvings[i] + 0x8000u) >> 16;
  }
  return whole >= 17 ? 0 : (acc + ((uint32_t{1} << whole) >> 1)) >> whole;
}

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
