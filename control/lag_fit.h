// Two lags from any record that starts at rest (M303 on seed000's higher-order hotends, whose
// probe outlasts the tune's model history): K/((τ1 s + 1)(τ2 s + 1)) obeys
// τ1τ2·ÿ + Σ·ẏ + y = K·u (Σ = τ1 + τ2, Π = τ1·τ2); integrated from rest,
//   K·∫u − ∫y = Σ·y + Π·ẏ
// for any input u, so least squares over samples (∫u, y, ẏ, ∫y) gives K, Σ and Π, and
// τ1,2 = (Σ ± √(Σ² − 4Π))/2. Portable, integer-only (Scaled: control/fixed_math.h), worked in
// pieces of one Scaled operation (≤ ~800 AVR cycles each) so that a control step stays cheap.
// Host test: against the double least squares on the same samples (test_lag_fit.cpp).
#pragma once

#include <stdint.h>

#include "control/fixed_math.h"

namespace control {

// The sums: m[0..5] = Σ r_i·r_j (i ≤ j: 00 01 02 11 12 22) and m[6..8] = Σ r_i·∫y for
// r = (∫u, y, ẏ); m[9], m[10] temporaries. Zeroed (all-zero bytes) before the first sample.
constexpr uint8_t kLagFitSums = 11;

// One piece (stage 1..36) of adding the sample x = (∫u × 2^12, y × 2^12, ẏ × 2^16, ∫y × 2^8)
// (any consistent units: duty × bins, °C, °C per bin, °C × bins; the same linear filter may be
// applied to all four, as the tune does) to the sums. Returns the next stage, 0 when the sample
// is in. x must not change until then.
uint8_t lag_fit_accumulate(fixed_math::Scaled* m, const int32_t* x, uint8_t stage);

// One piece (stage 1..42) of the solution; bin_ms: the samples' time unit in ms (≤ 65,535).
// Returns the next stage, 0 when done: x_q8 then holds K × 256 (x_q8[0]), τ1 and τ2 in s × 256
// (x_q8[1], x_q8[2]), or x_q8[1] = 0 when the sums give no real pair (Σ or Π ≤ 0, Σ² ≤ 4Π).
// The sums are used up (overwritten).
uint8_t lag_fit_solve(fixed_math::Scaled* m, uint16_t bin_ms, int32_t* x_q8, uint8_t stage);

}  // namespace control
