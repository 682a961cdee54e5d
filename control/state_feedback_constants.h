// The fixed-point constants of the state-feedback controller: produced by the host design
// (design/state_feedback_quantize.h, `hotend-design`), consumed by control/state_feedback.cpp.
// Portable (AVR and host), no floating point.
//
// Signals inside the controller are int32 "Q16 of their unit":
//   temperatures (model states x, set point, innovation)  °C above ambient × 2^16
//   duty-like signals (input bias d̂, plant input v)       duty × 2^(16+p), p = input_shift
// p makes 100 % duty about as large as the plant's full-power rise in °C (2^p ≈ DC gain), so
// every row below mixes numbers of similar size and one exponent per row keeps precision.
// Every coefficient is an int16 mantissa m with its row's shift s: value = m / 2^s.
#pragma once

#include <stdint.h>

namespace control {

constexpr uint8_t kSfMaxStates = 5;  // seed000's 5-state model
constexpr uint8_t kSfMaxDelay = 32;  // input-history samples (RAM: 2 bytes each, twice)
constexpr uint8_t kSfFirChunk = 16;  // predictor taps summed per step() call

// The law runs every `decimation` calls; the calls in between do its other work, so no single
// call exceeds the cycle budget: call 0 measurement update + law, call 1 the model's time update,
// calls 2.. the predictor sum for the next law update, kSfFirChunk taps each.
constexpr uint8_t state_feedback_min_decimation(uint8_t delay) {
  return static_cast<uint8_t>(2 + (delay + kSfFirChunk - 1) / kSfFirChunk);
}

struct StateFeedbackConstants {
  uint8_t n;            // model states, 1..kSfMaxStates
  uint8_t output_mask;  // modelled sensor rise = Σ x_j over set bits j
  uint8_t delay;        // D: periods of input dead time the observer and predictor use
  uint8_t decimation;   // law period in step() calls (× 128 ms), >= state_feedback_min_decimation
  uint8_t input_shift;  // p above (<= 10)
  int32_t ambient_q8;   // temperature the model calls 0 (°C × 256)

  // Observer time update, row i < n (delta form, so slow poles keep their precision):
  //   x_i += (phi_diag[i]·x_i + phi_off[i]·x_{phi_col[i]} + gamma_a[i]·v_a + gamma_b[i]·v_b)
  //          / 2^phi_shift[i]
  //   with phi_diag/phi_off the entries of Φ − I. The design's realisations (modal form, two
  //   lags or two nodes) couple each state to at most one other; v_a = v[k−D] + d̂,
  //   v_b = v[k−D+1] + d̂, in duty Q(16+p), with v the effective input (duty − fan loss).
  int16_t phi_diag[kSfMaxStates];
  int16_t phi_off[kSfMaxStates];
  uint8_t phi_col[kSfMaxStates];
  int16_t gamma_a[kSfMaxStates];
  int16_t gamma_b[kSfMaxStates];
  uint8_t phi_shift[kSfMaxStates];

  // Observer measurement update with e = y − Σ masked x (°C Q16):
  //   x_i += obs_gain[i]·e / 2^obs_shift[i];   d̂ += obs_gain[n]·e / 2^obs_shift[n].
  int16_t obs_gain[kSfMaxStates + 1];
  uint8_t obs_shift[kSfMaxStates + 1];

  // Control law in duty Q(16+p):
  //   v = (ff_gain·r − Σ fb_gain[j]·x_j − bias_gain·d̂) / 2^ctrl_shift − Σ_j fir[j−1]·u[k−j] /
  //   2^fir_shift (the fir products are duty Q16 × mantissa, scaled to Q(16+p) by fir_shift)
  int16_t fb_gain[kSfMaxStates];  // L·Φ^D · 2^p
  int16_t ff_gain;                // M · 2^p
  int16_t bias_gain;              // g_d = 1 + Σ h_j
  uint8_t ctrl_shift;
  int16_t fir[kSfMaxDelay];  // h_j · 2^p
  uint8_t fir_shift;

  // Part-fan feedforward: extra loss = fan_gain · (fan/255) · rise, in duty Q(16+p) per °C Q8;
  // added to the applied duty with weight 1 (it passes the heater's dead time, as the fan does).
  int16_t fan_gain;
  uint8_t fan_shift;

  // Steady state per °C of sensor rise, for bumpless start: x_j = share[j]·rise,
  // v = inv_gain·rise (duty Q(16+p) per °C Q16).
  int16_t ss_share[kSfMaxStates];
  uint8_t ss_share_shift;
  int16_t inv_gain;
  uint8_t inv_gain_shift;
};

// The model's zero (ambient_q8), as M311 accepts it: −100..300 °C.
constexpr int32_t kSfMinAmbientQ8 = -100L * 256;
constexpr int32_t kSfMaxAmbientQ8 = 300L * 256;

// Magnitude limits that keep every intermediate of control/state_feedback.cpp in int32, for any
// StepInput with |measured_q8|, |target_q8| <= 2^30 (readings are table-bounded, targets
// <= 275 °C) and any int16 mantissa. Derivation, with X = 2^27 (kSignalLimit, ±2048 °C Q16):
//  - measured/target − ambient: |ambient_q8| <= 300 °C·256 < 2^17, so the difference < 2^31;
//    to_q16 clamps it to ±X.
//  - mulhi16(m, x) = round(m·x/2^16): |m| <= 2^15 and |x| < 2^31 give |result| < 2^30. Every
//    signal a product sees is clamped to ±X (x̂ after either update, e, r, v_a, v_b, y) or
//    smaller (d̂ <= 2^26, duty Q15 · 2^(p+1) <= 2^26 with p <= 10; x̂ after prime() <= 2^28), so
//    each product is <= 2^26 + 1/2. The law's row (<= 7 products) < 2^29; scale() saturates at
//    ±2^28; Σ of 5 states + y < 5·2^28 + X; the predictor's 32 taps (int16·int16 >> 8) < 2^27;
//    the fan term (y>>8)·255 < 2^27. None of these depends on the constants.
//  - The one place a constant can overflow the law is the observer's time update: row i sums
//    acc = Σ mulhi16(m_k, s_k) over Φ−I diag/off and Γa/Γb (4 terms, |s_k| <= X), so
//    |acc| <= S_i·2^11 + 2 with S_i = Σ|m_k| <= 2^17, and delta = acc·2^−(phi_shift−16) (floor
//    shift with a residual < 2^24, or an exact left shift for phi_shift < 16); x̂ + delta is
//    then clamped to ±X. x̂ + delta fits int32 if |delta| <= 2^31 − 1 − X, which holds for
//    S_i <= 2^(phi_shift+3), i.e. the row's coefficients |Φ−I| + |Γa| + |Γb| sum to at most 8:
//      phi_shift <= 16: |delta| <= (2^(phi_shift+14) + 2)·2^(16−phi_shift) <= 2^30 + 2^17;
//      phi_shift >= 17: |delta| <= (2^(phi_shift+14) + 2)/2^(phi_shift−16) + 1 <= 2^30 + 2.
//    With phi_shift >= 14 every row passes (S_i <= 2^17). A discretised stable hotend model
//    has |Φ−I| < 1 and Γ ≈ gain·(1 − λ)/2^p < 2 (2^p within a factor 2 of the gain): M303's
//    designs reach 2.95 at the corners of M307's ranges (long decimated law periods).
// host_tests/ubsan_state_feedback_limits.cpp runs the law at these limits against a 64-bit
// reference under UBSan.
// |m| (≤ 2^15). noinline: four inlined copies in the row check cost more AVR flash than calls.
__attribute__((noinline)) inline uint32_t state_feedback_magnitude(int16_t m) {
  return static_cast<uint32_t>(m < 0 ? -static_cast<int32_t>(m) : m);
}

inline bool state_feedback_row_fits(const StateFeedbackConstants& k, uint8_t i) {
  const uint8_t shift = k.phi_shift[i];
  if (shift >= 14) return true;
  const uint32_t sum = state_feedback_magnitude(k.phi_diag[i]) + state_feedback_magnitude(k.phi_off[i]) +
                       state_feedback_magnitude(k.gamma_a[i]) + state_feedback_magnitude(k.gamma_b[i]);
  return sum <= (1UL << (shift + 3));
}

// Range checks the runtime relies on (shifts within what the arithmetic supports, sizes, the
// magnitude limits above). M311 W1, M303 U1 and the EEPROM loader all go through it.
inline bool state_feedback_constants_valid(const StateFeedbackConstants& k) {
  if (k.n < 1 || k.n > kSfMaxStates || k.delay > kSfMaxDelay) return false;
  if (k.ambient_q8 < kSfMinAmbientQ8 || k.ambient_q8 > kSfMaxAmbientQ8) return false;
  if (k.decimation < state_feedback_min_decimation(k.delay)) return false;
  if (k.input_shift > 10 || k.output_mask == 0) return false;
  if (k.output_mask >> k.n) return false;
  for (uint8_t i = 0; i < k.n; ++i)  // <= 40: the carried residual stays below 2^24
    if (k.phi_shift[i] > 40 || k.phi_col[i] >= k.n || !state_feedback_row_fits(k, i)) return false;
  for (uint8_t i = 0; i <= k.n; ++i)
    if (k.obs_shift[i] > 46) return false;
  return k.ctrl_shift <= 46 && k.fir_shift <= 46 && k.fan_shift <= 46 && k.ss_share_shift <= 46 &&
         k.inv_gain_shift <= 46;
}

}  // namespace control
