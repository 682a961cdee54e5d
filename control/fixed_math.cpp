// The Scaled (mantissa × 2^exponent) arithmetic of control/fixed_math.h. Magnitudes are handled
// as uint32 below 2^31 so that no step can overflow; the sign is carried beside them.
#include "control/fixed_math.h"

namespace fixed_math {
namespace {

constexpr uint32_t kLow = uint32_t{1} << 29;   // normalised |m| in [kLow, kHigh)
constexpr uint32_t kHigh = uint32_t{1} << 30;
constexpr int32_t kMaxExponent = 16000;       // |e| beyond: saturate / flush to zero
constexpr Scaled kOne{int32_t{1} << 29, -29};
constexpr Scaled kLn2{744261118, -30};  // ln 2 · 2^30, rounded

// noinline: inlined at its seven call sites (58 B of AVR flash as calls); design-time math only.
__attribute__((noinline)) uint32_t magnitude(int32_t m) { return m < 0 ? 0u - static_cast<uint32_t>(m) : static_cast<uint32_t>(m); }

// ±mag · 2^e, normalised (rounding once, halves up, when mag has more than 30 bits).
Scaled make(bool negative, uint32_t mag, int32_t e) {
  if (mag == 0) return Scaled{0, 0};
  while (mag >= kHigh) {
    mag = (mag >> 1) + (mag & 1u);  // may round up to kHigh: the loop halves once more
    ++e;
  }
  while (mag < kLow) {
    mag <<= 1;
    --e;
  }
  if (e < -kMaxExponent) return Scaled{0, 0};
  if (e > kMaxExponent) {
    e = kMaxExponent;
    mag = kHigh - 1;
  }
  const int32_t m = static_cast<int32_t>(mag);
  return Scaled{negative ? -m : m, static_cast<int16_t>(e)};
}

}  // namespace

uint16_t isqrt_u32(uint32_t x) {
  uint32_t root = 0;
  uint32_t bit = uint32_t{1} << 30;
  while (bit > x) bit >>= 2;
  while (bit != 0) {
    if (x >= root + bit) {
      x -= root + bit;
      root = (root >> 1) + bit;
    } else {
      root >>= 1;
    }
    bit >>= 2;
  }
  return static_cast<uint16_t>(root);
}

Scaled scaled(int32_t v, int16_t e) { return make(v < 0, magnitude(v), e); }

// The operations are not inlined into each other (exp_neg, ln): set-up code, where flash counts.
__attribute__((noinline)) Scaled add(Scaled a, Scaled b) {
  if (b.m == 0) return a;
  if (a.m == 0) return b;
  if (a.e < b.e) {
    const Scaled t = a;
    a = b;
    b = t;
  }
  const int16_t d = a.e - b.e;
  if (d > 30) return a;  // b is below a's rounding
  int32_t y = b.m;       // aligned to a, rounded (|y| < 2^30: no overflow)
  if (d > 0) y = (y + (int32_t{1} << (d - 1))) >> d;
  const int32_t sum = a.m + y;  // |sum| < 2^31
  return make(sum < 0, magnitude(sum), a.e);
}

__attribute__((noinline)) Scaled sub(Scaled a, Scaled b) { return add(a, neg(b)); }

// Shift-and-add over the 30 bits of |b|: acc = (acc + bit·|a|)/2 each step, so acc < 2^30 and
// acc + |a| < 2^31; the end value is |a·b|/2^30 less < 1 (the dropped bits), in [2^28 − 1, 2^30).
// Smaller than four 16×16 products on AVR (set-up code: flash counts more than ~600 cycles).
__attribute__((noinline)) Scaled mul(Scaled a, Scaled b) {
  if (a.m == 0 || b.m == 0) return Scaled{0, 0};
  const uint32_t x = magnitude(a.m);
  uint32_t y = magnitude(b.m), acc = 0;
  for (uint8_t i = 0; i < 30; ++i) {
    if (y & 1u) acc += x;
    y >>= 1;
    acc >>= 1;
  }
  return make((a.m < 0) != (b.m < 0), acc, static_cast<int32_t>(a.e) + b.e + 30);
}

// Restoring division: 31 quotient bits of |a|·2^30/|b| (|a|/|b| in (1/2, 2): q in (2^29, 2^31)),
// the remainder < 2|b| < 2^31 before each doubling; rounded by the next bit.
__attribute__((noinline)) Scaled div(Scaled a, Scaled b) {
  if (a.m == 0 || b.m == 0) return Scaled{0, 0};
  const uint32_t mb = magnitude(b.m);
  uint32_t r = magnitude(a.m), q = 0;
  for (uint8_t i = 0; i < 31; ++i) {
    q <<= 1;
    if (r >= mb) {
      r -= mb;
      q |= 1u;
    }
    r <<= 1;
  }
  if (r >= mb) ++q;
  return make((a.m < 0) != (b.m < 0), q, static_cast<int32_t>(a.e) - b.e - 30);
}

// noinline: LTO inlined it into each design's comparisons (76 B of AVR flash as a call).
__attribute__((noinline)) bool less(Scaled a, Scaled b) { return sub(a, b).m < 0; }

int32_t round_scaled(Scaled a, int16_t s) {
  const int32_t sh = static_cast<int32_t>(a.e) + s;
  uint32_t mag = magnitude(a.m);
  if (mag == 0) return 0;
  if (sh >= 0) {
    mag = sh > 1 ? 0x7FFFFFFFu : mag << sh;  // |m| < 2^30: one doubling still fits
  } else {
    if (sh < -31) return 0;
    const uint8_t n = static_cast<uint8_t>(-sh);
    mag = (mag + (uint32_t{1} << (n - 1))) >> n;  // halves away from zero
  }
  return a.m < 0 ? -static_cast<int32_t>(mag) : static_cast<int32_t>(mag);
}

// e^(−x) = (e^(−x/2^n))^(2^n) with x/2^n < 1/2, where the Taylor series of 1 − e^(−x) in Horner
// form, x·(1 − x/2·(1 − x/3·(… (1 − x/10)))), leaves out less than 2^-35·x; then n squarings
// (each doubles the relative error: n <= 6 for x < 32, the design's largest h/T). `complement`
// returns 1 − e^(−x) instead, straight from the series when x < 1/2 (relative precision).
Scaled exp_neg(Scaled x, bool complement) {
  if (x.m <= 0) return complement ? Scaled{0, 0} : kOne;
  if (x.e > -16) return complement ? kOne : Scaled{0, 0};  // x ≥ 2^14: e^(−x) below 2^-23000
  uint8_t n = 0;
  for (; x.e >= -30; ++n) --x.e;  // x ≥ 1/2 ⇔ e ≥ −30 (normalised)
  Scaled t = kOne;
  for (int8_t k = 10; k >= 2; --k) t = sub(kOne, div(mul(x, t), scaled(k)));
  t = mul(x, t);  // 1 − e^(−x/2^n)
  if (n == 0 && complement) return t;
  t = sub(kOne, t);
  while (n--) t = mul(t, t);
  return complement ? sub(kOne, t) : t;  // x ≥ 1/2 here: 1 − e^(−x) ≥ 0.39, no cancellation
}

// ln x for x > 0: ln x = −ln(1/x) below 1; above, Newton on e^z = x from the octave's linear
// log2 (|error| < 0.061): z += x·e^(−z) − 1, whose error e goes to e²/2: four steps reach the
// arithmetic's own precision.
Scaled ln(Scaled x) {
  if (x.m <= 0) return Scaled{0, 0};
  if (x.e < -29) return neg(ln(div(kOne, x)));  // x < 1 (1/x ≥ 1: one level of recursion)
  Scaled z = mul(kLn2, add(scaled(x.e + 29), scaled(x.m - (int32_t{1} << 29), -29)));
  for (uint8_t i = 0; i < 4; ++i) z = add(z, sub(mul(x, exp_neg(z)), kOne));
  return z;
}

}  // namespace fixed_math
