// Natural logarithm and exponential that the compiler can evaluate in constant expressions.
// <cmath> is not constexpr in C++14, and the thermistor tables must be computed by the compiler
// (avr-gcc 5.4 and host g++ alike), so we carry our own. Accuracy on the host (64-bit double):
// ~1e-15 relative over the ranges the thermistor code uses (checked in test_thermistor_math.cpp).
// avr-gcc 5.4's double is IEEE single, so compile-time results there are float-accurate
// (~1e-7 relative): the functions are templates on the floating type so that the host tests can
// re-run the same computation in `float` and check what the AVR compiler produces.
// Loops have fixed iteration caps, so they terminate whatever the floating-point width.
#pragma once

namespace cxmath {

// Blocks template argument deduction: ln(10) must mean ln<double>(10.0), not ln<int>.
template <class T> struct Identity { using type = T; };
template <class T> using NoDeduce = typename Identity<T>::type;

template <class Real = double> constexpr Real abs(NoDeduce<Real> x) { return x < 0 ? -x : x; }

// ln x for x > 0. Why this form: x = m·2^e with m in [√½, √2) keeps s = (m−1)/(m+1) within
// ±0.172, where ln m = 2·atanh s = 2(s + s³/3 + s⁵/5 + …) converges fast (16 terms: s^33 < 1e-25).
// x == 0 gives −inf, x < 0 gives NaN (as std::log).
template <class Real = double> constexpr Real ln(NoDeduce<Real> x) {
  const Real ln2 = Real(0.69314718055994530942);
  const Real sqrt2 = Real(1.41421356237309504880);
  if (x == 0) return -__builtin_huge_val();
  if (!(x > 0)) return __builtin_nan("");
  int e = 0;
  for (int i = 0; i < 2100 && x >= sqrt2; ++i) { x *= Real(0.5); ++e; }
  for (int i = 0; i < 2100 && x < sqrt2 * Real(0.5); ++i) { x *= Real(2); --e; }
  const Real s = (x - 1) / (x + 1);
  const Real s2 = s * s;
  Real term = s;
  Real sum = 0;
  for (int k = 1; k <= 31; k += 2) {
    sum += term / k;
    term *= s2;
  }
  return 2 * sum + e * ln2;
}

// e^x. Why this form: x = k·ln2 + r with |r| ≤ ln2/2 makes the Taylor series of e^r converge in
// ~18 terms to double precision; 2^k is then applied exactly by repeated doubling/halving.
// Arguments beyond the double range saturate to inf / 0 instead of looping.
template <class Real = double> constexpr Real exp(NoDeduce<Real> x) {
  const Real ln2 = Real(0.69314718055994530942);
  if (x > 709) return __builtin_huge_val();
  if (x < -745) return 0;
  const long k = static_cast<long>(x / ln2 + (x >= 0 ? Real(0.5) : Real(-0.5)));
  const Real r = x - k * ln2;
  Real term = 1;
  Real sum = 1;
  for (int n = 1; n <= 22; ++n) {
    term *= r / n;
    sum += term;
  }
  for (long i = 0; i < k; ++i) sum *= 2;
  for (long i = 0; i > k; --i) sum *= Real(0.5);
  return sum;
}

}  // namespace cxmath
