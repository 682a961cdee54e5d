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
constexpr uint16_t sat_u16(int32_t x) {
  return x < 0 ? uint16_t{0} : (x > 0xFFFF ? uint16_t{0xFFFF} : static_cast<uint16_t>(x));
}

// x / 2^n rounded to nearest, halves toward +∞ (a plain >> would floor: a bias of ½ LSB that
// integrators accumulate). Needs |x| + 2^(n−1) ≤ INT32_MAX and 1 ≤ n ≤ 30.
constexpr int32_t shr_round(int32_t x, uint8_t n) { return (x + (int32_t{1} << (n - 1))) >> n; }
constexpr uint32_t shr_round(uint32_t x, uint8_t n) { return (x + (uint32_t{1} << (n - 1))) >> n; }

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
constexpr int32_t mul_q16(int32_t x, uint16_t a_q16) {
  return mul_i16_u16(static_cast<int16_t>(static_cast<uint32_t>(x) >> 16), a_q16) +
         static_cast<int32_t>(mul_u16(static_cast<uint16_t>(x), a_q16) >> 16);
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
