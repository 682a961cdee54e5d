// Natural logarithm and exponential that the compiler can evaluate in constant expressions.
// <cmath> is not constexpr in C++14, and the thermistor tables must be computed by the compiler
// (avr-gcc 5.4 and host g++ alike), so we carry our own. Accuracy on the host (64-bit double):
// ~1e-15 relative over the ranges the thermistor code uses (checked in test_constexpr_math.cpp).
// On AVR, avr-gcc 5.4's double is 32-bit, so compile-time results there are float-accurate
// (~1e-7 relative) — ample for tables whose entries are rounded to 1/64 ADC code and 1/256 °C.
// Loops have fixed iteration caps, so they terminate whatever the floating-point width.
#pragma once

namespace cxmath {

constexpr double kLn2 = 0.69314718055994530942;    // ln 2
constexpr double kSqrt2 = 1.41421356237309504880;  // √2

constexpr double abs(double x) { return x < 0 ? -x : x; }

// ln x for x > 0. Why this form: x = m·2^e with m in [√½, √2) keeps s = (m−1)/(m+1) within
// ±0.172, where ln m = 2·atanh s = 2(s + s³/3 + s⁵/5 + …) converges fast (15 terms: s^31 < 1e-23).
// x == 0 gives −inf, x < 0 gives NaN (as std::log).
constexpr double ln(double x) {
  if (x == 0) return -__builtin_huge_val();
  if (!(x > 0)) return __builtin_nan("");
  int e = 0;
  for (int i = 0; i < 2100 && x >= kSqrt2; ++i) { x *= 0.5; ++e; }
  for (int i = 0; i < 2100 && x < kSqrt2 * 0.5; ++i) { x *= 2.0; --e; }
  const double s = (x - 1.0) / (x + 1.0);
  const double s2 = s * s;
  double term = s;
  double sum = 0;
  for (int k = 1; k <= 31; k += 2) {
    sum += term / k;
    term *= s2;
  }
  return 2.0 * sum + e * kLn2;
}

// e^x. Why this form: x = k·ln2 + r with |r| ≤ ln2/2 makes the Taylor series of e^r converge in
// ~18 terms to double precision; 2^k is then applied exactly by repeated doubling/halving.
// Results beyond ±700 saturate to inf / 0 instead of looping.
constexpr double exp(double x) {
  if (x > 709.0) return __builtin_huge_val();
  if (x < -745.0) return 0.0;
  const long k = static_cast<long>(x / kLn2 + (x >= 0 ? 0.5 : -0.5));
  const double r = x - k * kLn2;
  double term = 1.0;
  double sum = 1.0;
  for (int n = 1; n <= 22; ++n) {
    term *= r / n;
    sum += term;
  }
  for (long i = 0; i < k; ++i) sum *= 2.0;
  for (long i = 0; i > k; --i) sum *= 0.5;
  return sum;
}

}  // namespace cxmath
