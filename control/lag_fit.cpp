// Two-lag least-squares fit (control/lag_fit.h), in Scaled arithmetic (control/fixed_math.h).
#include "control/lag_fit.h"

namespace control {

uint8_t lag_fit_accumulate(fixed_math::Scaled* m, const int32_t* x, uint8_t stage) {
  using namespace fixed_math;
  const uint8_t k = static_cast<uint8_t>((stage - 1) >> 2);  // 0–8
  const uint8_t piece = static_cast<uint8_t>((stage - 1) & 3);
  if (piece < 2) {
    // k 0–5: the pairs 00 01 02 11 12 22; 6–8: 03 13 23 (no table: it would take RAM on AVR).
    uint8_t i = 0, j = 3;
    if (k > 5) {
      i = static_cast<uint8_t>(k - 6);
    } else {
      i = k > 4 ? 2 : (k > 2 ? 1 : 0);
      j = static_cast<uint8_t>(k - (i == 0 ? 0 : i + 1));
    }
    const uint8_t c = piece == 0 ? i : j;
    m[9 + piece] = scaled(x[c], c == 2 ? -16 : (c == 3 ? -8 : -12));
  } else if (piece == 2) {
    m[9] = mul(m[9], m[10]);
  } else {
    m[k] = add(m[k], m[9]);
    if (k == 8) return 0;
  }
  return static_cast<uint8_t>(stage + 1);
}

namespace {
enum FitOp : uint8_t { kFitDiv, kFitSubMul, kFitMul, kFitAdd };
// m[d] = m[a] / m[b], m[d] − m[a]·m[b], m[a]·m[b] or m[a] + m[b]: one call per piece keeps
// lag_fit_solve small (its pieces inline were 1.7 KB of AVR flash).
__attribute__((noinline)) void fit_op(fixed_math::Scaled* m, FitOp op, uint8_t d, uint8_t a, uint8_t b) {
  using namespace fixed_math;
  switch (op) {
    case kFitDiv: m[d] = div(m[a], m[b]); break;
    case kFitSubMul: m[d] = sub(m[d], mul(m[a], m[b])); break;
    case kFitMul: m[d] = mul(m[a], m[b]); break;
    default: m[d] = add(m[a], m[b]); break;
  }
}
}  // namespace

uint8_t lag_fit_solve(fixed_math::Scaled* m, uint16_t bin_ms, int32_t* x_q8, uint8_t stage) {
  using namespace fixed_math;
  // m: 0 m00, 1 m01, 2 m02, 3 m11, 4 m12, 5 m22, 6 v0, 7 v1, 8 v2, 9 and 10 temporaries
  switch (stage) {
    case 1: fit_op(m, kFitDiv, 9, 1, 0); break;     // l10 = m01/m00
    case 2: fit_op(m, kFitSubMul, 3, 9, 1); break;  // a11
    case 3: fit_op(m, kFitSubMul, 4, 9, 2); break;  // a12
    case 4: fit_op(m, kFitSubMul, 7, 9, 6); break;  // w1
    case 5: fit_op(m, kFitDiv, 9, 2, 0); break;     // l20 = m02/m00
    case 6: fit_op(m, kFitSubMul, 5, 9, 2); break;  // a22
    case 7: fit_op(m, kFitSubMul, 8, 9, 6); break;  // w2
    case 8: fit_op(m, kFitDiv, 9, 4, 3); break;     // l21 = a12/a11
    case 9: fit_op(m, kFitSubMul, 5, 9, 4); break;
    case 10: fit_op(m, kFitSubMul, 8, 9, 7); break;
    case 11: fit_op(m, kFitDiv, 8, 8, 5); break;    // −Π
    case 12: fit_op(m, kFitSubMul, 7, 4, 8); break;
    case 13: fit_op(m, kFitDiv, 7, 7, 3); break;    // −Σ
    case 14: fit_op(m, kFitSubMul, 6, 1, 7); break;
    case 15: fit_op(m, kFitSubMul, 6, 2, 8); break;
    case 16: fit_op(m, kFitDiv, 6, 6, 0); break;    // K
    case 17:
      // Σ (m7), Π (m8), Σ² (m5).
      m[7] = neg(m[7]);
      m[8] = neg(m[8]);
      fit_op(m, kFitMul, 5, 7, 7);
      break;
    case 18:
      // Σ² − 4Π; no real pair (or a negative Σ or Π): no fit.
      m[9] = ldexp(m[8], 2);
      m[5] = sub(m[5], m[9]);
      if (is_negative(m[7]) || is_negative(m[8]) || m[8].m == 0 || is_negative(m[5]) || m[5].m == 0) {
        x_q8[1] = 0;
        return 0;
      }
      m[4] = m[7];
      break;
    case 35: fit_op(m, kFitAdd, 4, 7, 4); break;  // 2·τ1
    case 36: m[4] = ldexp(m[4], -1); fit_op(m, kFitDiv, 9, 8, 4); break;  // τ1, τ2 = Π/τ1 (bins)
    case 37: x_q8[0] = round_scaled(m[6], 8); break;  // K
    // Bins to s × 256: × bin_ms / 1000 (round_scaled saturates at 2^31: τ > 8,388 s, beyond M307).
    case 38: m[10] = scaled(bin_ms); break;
    case 39: fit_op(m, kFitMul, 4, 4, 10); break;
    case 40: fit_op(m, kFitMul, 9, 9, 10); break;
    case 41: x_q8[1] = round_scaled(m[4], 8) / 1000; break;  // (truncated: < 1/256 s)
    case 42: x_q8[2] = round_scaled(m[9], 8) / 1000; return 0;
    default:
      // 19–34: Newton, r ← (r + d/r)/2.
      if (stage & 1) {
        fit_op(m, kFitDiv, 9, 5, 4);
      } else {
        fit_op(m, kFitAdd, 4, 4, 9);
        m[4] = ldexp(m[4], -1);
      }
      break;
  }
  return static_cast<uint8_t>(stage + 1);
}

}  // namespace control
