// Fixed-point helpers shared by the control code. Q notation: a `_qN` suffix means the integer
// holds value × 2^N (temp_q8 = °C × 256, duty_q16 = fraction × 65536 with 65535 as 100 %).
// Everything is integer-only and constexpr, so the same code runs on AVR (no FPU, 8-bit ALU with
// an 8×8 hardware multiplier) and on the host. Right shifts of negative numbers are arithmetic:
// GCC documents this for its signed >> (implementation-defined in C++14), and both targets are GCC.
#pragma once

#include <stdint.h>

namespace fixed {

// Clamps x to [lo, hi] (lo ≤ hi).
template <class T> constexpr T clamp(T x, T lo, T hi) { return x < lo ? lo : (hi < x ? hi : x); }

// a + b, saturated to the int32 range instead of wrapping (signed overflow is undefined).
constexpr int32_t add_sat(int32_t a, int32_t b) {
  return (b > 0 && a > INT32_MAX - b) ? INT32_MAX : (b < 0 && a < INT32_MIN - b) ? INT32_MIN : a + b;
}

// Saturates an int32 to the uint16 range: the last step from an internal value to duty_q16.
// noinline (here and mul_q16): with LTO each use was inlined, 556 bytes of AVR flash in all for
// a call's ~10 cycles (the fuzzy and PID steps measured unchanged, simavr).
__attribute__((noinline)) constexpr uint16_t sat_u16(int32_t x) {
  return x < 0 ? uint16_t{0} : (x > 0xFFFF ? uint16_t{0xFFFF} : static_cast<uint16_t>(x));
}

// x / 2^n rounded to nearest, halves toward +∞ (a plain >> would floor: a bias of ½ LSB that
// integrators accumulate). Needs |x| + 2^(n−1) ≤ INT32_MAX and 1 ≤ n ≤ 30.
// For n > 8 the first 8 bits go by a plain >> 8 (a byte move on AVR, where avr-gcc -Os otherwise
// shifts one bit per loop turn: 89 vs 38 cycles for n = 11). Same result, since
// ⌊(⌊x/2^8⌋ + 2^(n−9)) / 2^(n−8)⌋ = ⌊(x + 2^(n−1)) / 2^n⌋.
constexpr int32_t shr_round(int32_t x, uint8_t n) {
  return n > 8 ? shr_round(x >> 8, static_cast<uint8_t>(n - 8)) : (x + (int32_t{1} << (n - 1))) >> n;
}
constexpr uint32_t shr_round(uint32_t x, uint8_t n) {
  return n > 8 ? shr_round(x >> 8, static_cast<uint8_t>(n - 8)) : (x + (uint32_t{1} << (n - 1))) >> n;
}

// 16×16 → 32-bit products. Spelled out so avr-gcc uses its widening multiply (a few MULs)
// instead of a full 32×32 library multiply.
constexpr uint32_t mul_u16(uint16_t a, uint16_t b) {
  return static_cast<uint32_t>(a) * static_cast<uint32_t>(b);
}
constexpr int32_t mul_i16(int16_t a, int16_t b) {
  return static_cast<int32_t>(a) * static_cast<int32_t>(b);
}
constexpr int32_t mul_i16_u16(int16_t a, uint16_t b) {
  return static_cast<int32_t>(a) * static_cast<int32_t>(b);
}

// floor(x · a_q16 / 2^16) for any int32 x and a_q16 in [0, 65535] (a factor in [0, 1)), exact and
// without a 64-bit product: x = hi·2^16 + lo with lo in [0, 65535], so
// x·a/2^16 = hi·a + lo·a/2^16, where hi·a fits int32 and lo·a fits uint32. Two 16×16 multiplies.
// (hi is taken through an unsigned shift: with `x >> 16` GCC folds the casts away and falls
// back to a 32×32 library multiply on AVR.)
__attribute__((noinline)) constexpr int32_t mul_q16(int32_t x, uint16_t a_q16) {
  return mul_i16_u16(static_cast<int16_t>(static_cast<uint32_t>(x) >> 16), a_q16) +
         static_cast<int32_t>(mul_u16(static_cast<uint16_t>(x), a_q16) >> 16);
}

// Same, rounded to nearest (halves up) instead of floored: no bias when results are accumulated.
constexpr int32_t mul_q16_round(int32_t x, uint16_t a_q16) {
  return mul_i16_u16(static_cast<int16_t>(static_cast<uint32_t>(x) >> 16), a_q16) +
         static_cast<int32_t>((mul_u16(static_cast<uint16_t>(x), a_q16) + 0x8000u) >> 16);
}

// A non-negative multiplier with 16 fraction bits, held as whole part + fraction so that applying
// it needs one 32-bit and two 16×16 multiplies instead of a 64-bit product.
struct Multiplier {
  uint32_t whole;
  uint16_t frac_q16;
};

// round(x · m). The caller keeps |x|·(m.whole + 1) ≤ 2^30 (so nothing overflows). A zero fraction
// skips its two multiplies (see without_small_fraction). Always inlined: once several control
// steps used it, avr-gcc -Os made it a call, which added ~380 cycles to Pid::step (simavr).
__attribute__((always_inline)) constexpr int32_t mul_round(int32_t x, Multiplier m) {
  return m.frac_q16 == 0 ? x * static_cast<int32_t>(m.whole)
                         : x * static_cast<int32_t>(m.whole) + mul_q16_round(x, m.frac_q16);
}

// m rounded to a whole number when that changes it by at most 2^-11 relative (whole ≥ 1024):
// makes mul_round one multiply instead of three for all but small coefficients.
constexpr Multiplier without_small_fraction(Multiplier m) {
  return m.whole < 1024 ? m : Multiplier{m.frac_q16 >= 0x8000 ? m.whole + 1 : m.whole, 0};
}

struct QuotientRemainder {
  uint32_t quotient;
  uint32_t remainder;
};

// a·b = q·c + r, 0 ≤ r < c, with 32-bit arithmetic only (for set-up code such as PID configuration:
// avoids linking 64-bit multiply/divide into the firmware). Binary long multiplication modulo c:
// walk b's bits from the top keeping a·(bits so far) = q·c + r. Needs 1 ≤ c ≤ 2^31 and
// q < 2^32. About 32 iterations: not for per-sample code.
__attribute__((noinline)) constexpr QuotientRemainder mul_divmod_u32(uint32_t a, uint32_t b, uint32_t c) {
  const uint32_t a_div = a / c;
  const uint32_t a_mod = a % c;
  uint32_t q = 0;
  uint32_t r = 0;
  for (int8_t bit = 31; bit >= 0; --bit) {
    q <<= 1;
    r <<= 1;  // r < c ≤ 2^31: no overflow
    if (r >= c) { r -= c; ++q; }
    if ((b >> bit) & 1u) {
      q += a_div;
      r += a_mod;  // < 2c ≤ 2^32
      if (r >= c) { r -= c; ++q; }
    }
  }
  return QuotientRemainder{q, r};
}

// round(a·b / c), halves up; same preconditions.
constexpr uint32_t mul_div_u32(uint32_t a, uint32_t b, uint32_t c) {
  const QuotientRemainder qr = mul_divmod_u32(a, b, c);
  return qr.remainder >= c - qr.remainder ? qr.quotient + 1 : qr.quotient;
}

// The Multiplier nearest to a·b/c (|error| ≤ 2^-17); same preconditions as mul_divmod_u32.
constexpr Multiplier multiplier_ratio(uint32_t a, uint32_t b, uint32_t c) {
  const QuotientRemainder qr = mul_divmod_u32(a, b, c);
  const uint32_t frac_q16 = mul_div_u32(qr.remainder, 65536, c);  // ≤ 65536: may carry
  return frac_q16 > 0xFFFF ? Multiplier{qr.quotient + 1, 0}
                           : Multiplier{qr.quotient, static_cast<uint16_t>(frac_q16)};
}

// Compile-time conversions for constants (e.g. default gains). Never call them at run time in
// the firmware: they are double arithmetic and would link soft-float routines on AVR.
constexpr int32_t from_double(double x, uint8_t frac_bits) {
  return static_cast<int32_t>(x * static_cast<double>(int32_t{1} << frac_bits) + (x < 0 ? -0.5 : 0.5));
}
constexpr double to_double(int32_t x, uint8_t frac_bits) {
  return static_cast<double>(x) / static_cast<double>(int32_t{1} << frac_bits);
}

}  // namespace fixed
