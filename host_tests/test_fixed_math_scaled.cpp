// fixed_math::Scaled (control/fixed_math.h, the mantissa × 2^exponent numbers of the on-board
// state-feedback design) against double and <cmath>: the worst error of each operation over its
// domain, printed and bounded.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "control/fixed_math.h"

namespace {

using fixed_math::Scaled;

double to_double(Scaled s) { return std::ldexp(static_cast<double>(s.m), s.e); }

Scaled from_double(double v) {
  int e = 0;
  const double f = std::frexp(v, &e);  // |f| in [1/2, 1)
  return fixed_math::scaled(static_cast<int32_t>(std::lround(std::ldexp(f, 30))), static_cast<int16_t>(e - 30));
}

bool normalised(Scaled s) {
  const int32_t a = s.m < 0 ? -s.m : s.m;
  return s.m == 0 ? s.e == 0 : (a >= (int32_t{1} << 29) && a < (int32_t{1} << 30));
}

struct Rng {
  uint64_t s = 88172645463325252ull;
  double uniform() {  // [0, 1)
    s ^= s << 13;
    s ^= s >> 7;
    s ^= s << 17;
    return static_cast<double>(s >> 11) / 9007199254740992.0;
  }
  // ± 10^[-12, 12)
  double wide() { return (uniform() < 0.5 ? -1 : 1) * std::pow(10.0, 24 * uniform() - 12); }
};

double rel(double got, double want) { return want == 0 ? std::fabs(got) : std::fabs(got - want) / std::fabs(want); }

TEST(FixedMathScaled, IntegersAreExactAndNormalised) {
  for (int32_t v : {0, 1, -1, 2, 3, 1000, -65533, 536870911, 536870912, 1073741823, 1073741824, INT32_MAX, INT32_MIN + 1}) {
    const Scaled s = fixed_math::scaled(v);
    EXPECT_TRUE(normalised(s)) << v;
    // Up to 30 bits exact; wider values round once.
    EXPECT_LE(std::fabs(to_double(s) - v), std::fabs(static_cast<double>(v)) * std::ldexp(1.0, -30)) << v;
  }
}

TEST(FixedMathScaled, ArithmeticWorstRelativeError) {
  Rng rng;
  double worst_mul = 0, worst_div = 0, worst_add = 0;
  for (int i = 0; i < 200000; ++i) {
    const double x = rng.wide(), y = rng.wide();
    const Scaled a = from_double(x), b = from_double(y);
    const double xa = to_double(a), yb = to_double(b);  // the operands as represented
    const Scaled p = fixed_math::mul(a, b), q = fixed_math::div(a, b), s = fixed_math::add(a, b);
    ASSERT_TRUE(normalised(p) && normalised(q) && normalised(s));
    worst_mul = std::fmax(worst_mul, rel(to_double(p), xa * yb));
    worst_div = std::fmax(worst_div, rel(to_double(q), xa / yb));
    // Sums: relative to the larger operand (what cancels is gone in any format).
    worst_add = std::fmax(worst_add, std::fabs(to_double(s) - (xa + yb)) / std::fmax(std::fabs(xa), std::fabs(yb)));
    EXPECT_EQ(fixed_math::less(a, b), xa < yb);
  }
  std::printf("Scaled: worst relative error mul %.2e, div %.2e, add %.2e (2^-29 = %.2e)\n", worst_mul, worst_div,
              worst_add, std::ldexp(1.0, -29));
  EXPECT_LT(worst_mul, std::ldexp(1.0, -27));
  EXPECT_LT(worst_div, std::ldexp(1.0, -28));
  EXPECT_LT(worst_add, std::ldexp(1.0, -28));
}

TEST(FixedMathScaled, ZeroAndExtremes) {
  const Scaled zero = fixed_math::scaled(0), one = fixed_math::scaled(1);
  EXPECT_EQ(fixed_math::mul(zero, one).m, 0);
  EXPECT_EQ(fixed_math::div(one, zero).m, 0);  // defined, callers exclude it
  EXPECT_EQ(fixed_math::sub(one, one).m, 0);
  EXPECT_EQ(fixed_math::add(zero, one).m, one.m);
  // Far below / above the exponent range: flushed / saturated, never wrapped.
  const Scaled tiny = fixed_math::ldexp(one, -15000), huge = fixed_math::ldexp(one, 15000);
  EXPECT_EQ(fixed_math::mul(tiny, tiny).m, 0);
  EXPECT_GT(fixed_math::mul(huge, huge).m, 0);
  EXPECT_EQ(fixed_math::mul(huge, huge).e, 16000);
  EXPECT_EQ(fixed_math::exp_neg(fixed_math::scaled(20000)).m, 0);
}

TEST(FixedMathScaled, RoundingHalvesAwayFromZero) {
  using fixed_math::round_scaled;
  EXPECT_EQ(round_scaled(fixed_math::scaled(5, -1), 0), 3);    // 2.5
  EXPECT_EQ(round_scaled(fixed_math::scaled(-5, -1), 0), -3);  // −2.5
  EXPECT_EQ(round_scaled(fixed_math::scaled(7, -2), 0), 2);    // 1.75
  EXPECT_EQ(round_scaled(fixed_math::scaled(-7, -3), 1), -2);  // −1.75
  EXPECT_EQ(round_scaled(fixed_math::scaled(1), 40), 0x7FFFFFFF);
  EXPECT_EQ(round_scaled(fixed_math::scaled(1), -40), 0);
  Rng rng;
  for (int i = 0; i < 100000; ++i) {
    const double x = (rng.uniform() - 0.5) * 131068;
    const Scaled a = from_double(x);
    const double xa = to_double(a);
    const double want = xa < 0 ? std::ceil(xa - 0.5) : std::floor(xa + 0.5);
    ASSERT_EQ(round_scaled(a, 0), static_cast<int32_t>(want)) << xa;
  }
}

TEST(FixedMathScaled, ExpNegAndOneMinusExpNegWorstRelativeError) {
  double worst_e = 0, worst_1m = 0, at_e = 0, at_1m = 0;
  for (double x = 1e-9; x < 40; x *= 1.0007) {
    const Scaled s = from_double(x);
    const double xs = to_double(s);
    // The squarings double the error each (x/2^n < 1/2): relative to 1 + x.
    const double e = rel(to_double(fixed_math::exp_neg(s)), std::exp(-xs)) / (1 + xs);
    const double m = rel(to_double(fixed_math::one_minus_exp_neg(s)), -std::expm1(-xs));
    if (e > worst_e) { worst_e = e; at_e = xs; }
    if (m > worst_1m) { worst_1m = m; at_1m = xs; }
  }
  std::printf("exp_neg: worst relative error / (1 + x) %.2e at x = %.4g; one_minus_exp_neg: relative %.2e at x = %.4g\n", worst_e, at_e,
              worst_1m, at_1m);
  EXPECT_LT(worst_e, std::ldexp(1.0, -26));
  EXPECT_LT(worst_1m, std::ldexp(1.0, -25));
  EXPECT_EQ(fixed_math::exp_neg(fixed_math::scaled(0)).m, int32_t{1} << 29);
  EXPECT_EQ(fixed_math::one_minus_exp_neg(fixed_math::scaled(0)).m, 0);
}

TEST(FixedMathScaled, LnWorstError) {
  double worst = 0, at = 0;  // |error| / (1 + |ln x|)
  for (double x = 1e-9; x < 1e9; x *= 1.0013) {
    const Scaled s = from_double(x);
    const double xs = to_double(s), want = std::log(xs);
    const double err = std::fabs(to_double(fixed_math::ln(s)) - want) / (1 + std::fabs(want));
    if (err > worst) { worst = err; at = xs; }
  }
  // The pole rule's ln(K/(K − 185 K)), K_q8 from 186 to 2000 °C: relative.
  double worst_rule = 0;
  for (int32_t k = 186 * 256; k <= 2000 * 256; k += 37) {
    const double want = std::log(static_cast<double>(k) / (k - 185 * 256));
    const Scaled ratio = fixed_math::div(fixed_math::scaled(k), fixed_math::scaled(k - 185 * 256));
    worst_rule = std::fmax(worst_rule, rel(to_double(fixed_math::ln(ratio)), want));
  }
  std::printf("ln: worst |error|/(1 + |ln x|) %.2e at x = %.4g; pole rule relative %.2e\n", worst, at, worst_rule);
  EXPECT_LT(worst, std::ldexp(1.0, -25));
  EXPECT_LT(worst_rule, std::ldexp(1.0, -24));
  EXPECT_EQ(fixed_math::ln(fixed_math::scaled(0)).m, 0);
  EXPECT_EQ(fixed_math::ln(fixed_math::scaled(1)).m, 0);
}

}  // namespace
