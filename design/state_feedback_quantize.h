// Turns a double-precision Design into the runtime's fixed-point control::StateFeedbackConstants
// (formats: control/state_feedback_constants.h). Host-side double, header-only, portable.
//
// The feedforward M is recomputed from the *quantised* model and gains, so the fixed-point loop
// has unit static gain exactly for the numbers it uses: with L·g ≈ M·G ≈ 600 on slow models,
// a 2^-15 mismatch between independently rounded M and L would otherwise leave ~2 % offset
// that no observer can see (it sits in the law, not in the model).
#pragma once

#include "control/state_feedback_constants.h"
#include "design/state_feedback_design.h"

namespace design {

// Largest shift s <= max_shift with every |round(v·2^s)| <= 32767; -1 if even s = 0 overflows.
// `step` 8 keeps s − 16 a multiple of 8 (rows the runtime shifts every period: byte moves on
// AVR instead of bit loops) at the price of 8–15 significant bits instead of 15; `step` 4
// keeps 12–15 bits and leaves at most 3 single-bit shifts.
inline int choose_shift(const double* v, int count, int max_shift, int step = 1) {
  double big = 0;
  for (int i = 0; i < count; ++i) big = fabs_(v[i]) > big ? fabs_(v[i]) : big;
  if (big == 0) return 16;
  for (int s = max_shift; s >= 0; --s) {
    if ((s + 64 - 16) % step != 0) continue;
    double scaled = big;
    for (int i = 0; i < s; ++i) scaled *= 2;
    if (scaled + 0.5 < 32767.0) return s;
  }
  return -1;
}

inline double pow2(int s) {
  double r = 1;
  for (int i = 0; i < (s < 0 ? -s : s); ++i) r *= 2;
  return s < 0 ? 1 / r : r;
}

inline int16_t mantissa(double v, int shift) {
  const double x = v * pow2(shift);
  return static_cast<int16_t>(x < 0 ? x - 0.5 : x + 0.5);
}

inline double value(int16_t m, int shift) { return m / pow2(shift); }

// Quantises `count` values at one shared exponent. False on overflow.
inline bool quantize_row(const double* v, int count, int max_shift, int16_t* out, uint8_t* shift,
                         int step = 1) {
  const int s = choose_shift(v, count, max_shift, step);
  if (s < 0) return false;
  for (int i = 0; i < count; ++i) out[i] = mantissa(v[i], s);
  *shift = static_cast<uint8_t>(s);
  return true;
}

// Returns nullptr on success, else what went wrong.
inline const char* quantize(const Design& d, double fan_loss_per_k, control::StateFeedbackConstants* k) {
  if (d.error) return d.error;
  *k = control::StateFeedbackConstants();
  const int n = d.real.model.n;
  k->n = static_cast<uint8_t>(n);
  k->output_mask = static_cast<uint8_t>(d.real.output_mask);
  k->delay = static_cast<uint8_t>(d.zoh.delay);
  k->decimation = static_cast<uint8_t>(d.decimation);
  int p = 0;  // 2^p ≈ DC gain (p + 0.5 > log2 G)
  while (p < 10 && pow2(p) * 1.41421356 < d.dc_gain) ++p;
  k->input_shift = static_cast<uint8_t>(p);
  const double amb_q8 = d.real.model.ambient_c * 256;
  k->ambient_q8 = static_cast<int32_t>(amb_q8 < 0 ? amb_q8 - 0.5 : amb_q8 + 0.5);
  const double two_p = pow2(p);

  // Observer model rows, then the model those integers actually describe.
  Mat phi_q = identity(n), gam_q = zeros(n, 1);
  for (int i = 0; i < n; ++i) {
    int col = i;  // the one other state this row may depend on
    for (int j = 0; j < n; ++j) {
      if (j == i || d.zoh.phi(i, j) == 0) continue;
      if (col != i) return "a state row couples to more than one other state";
      col = j;
    }
    double row[4] = {d.zoh.phi(i, i) - 1.0, col != i ? d.zoh.phi(i, col) : 0.0,
                     d.zoh.gamma_a(i, 0) / two_p, d.zoh.gamma_b(i, 0) / two_p};
    int16_t m[4];
    // Nibble-aligned exponent: >= 12 significant bits, at most 3 single-bit shift steps on AVR.
    if (!quantize_row(row, 4, 40, m, &k->phi_shift[i], 4)) return "state matrix out of range";
    k->phi_diag[i] = m[0];
    k->phi_off[i] = m[1];
    k->phi_col[i] = static_cast<uint8_t>(col != i ? col : 0);
    phi_q(i, i) += value(m[0], k->phi_shift[i]);
    if (col != i) phi_q(i, col) += value(m[1], k->phi_shift[i]);
    k->gamma_a[i] = m[2];
    k->gamma_b[i] = m[3];
    gam_q(i, 0) = (value(m[2], k->phi_shift[i]) + value(m[3], k->phi_shift[i])) * two_p;
  }
  Mat g_q;  // steady state per unit input of the quantised model
  if (!solve(identity(n) - phi_q, gam_q, &g_q)) return "quantised model has a pole at z = 1";
  const double gain_q = (d.real.model.c * g_q)(0, 0);

  for (int i = 0; i <= n; ++i) {
    const double kv = i < n ? d.k_obs(i, 0) : d.k_obs(n, 0) * two_p;
    if (!quantize_row(&kv, 1, 40, &k->obs_gain[i], &k->obs_shift[i], 8))
      return "observer gain out of range";
  }

  double fir[control::kSfMaxDelay];
  for (int j = 0; j < d.zoh.delay; ++j) fir[j] = d.h[j] * two_p;
  if (!quantize_row(fir, d.zoh.delay, 46, k->fir, &k->fir_shift))
    return "predictor gains out of range";
  double sum_h = 0;
  for (int j = 0; j < d.zoh.delay; ++j) sum_h += value(k->fir[j], k->fir_shift) / two_p;

  // Law row: quantise L first, then M (and g_d) consistent with the quantised numbers.
  double law[control::kSfMaxStates + 2];
  int16_t lm[control::kSfMaxStates + 2];
  for (int j = 0; j < n; ++j) law[j] = d.lx(0, j) * two_p;
  law[n] = (1 + sum_h) * 1.01;  // headroom: the final M, g_d differ slightly
  law[n + 1] = d.m * two_p * 1.01;
  if (!quantize_row(law, n + 2, 46, lm, &k->ctrl_shift)) return "feedback gains out of range";
  double lg = 0;
  for (int j = 0; j < n; ++j) {
    k->fb_gain[j] = lm[j];
    lg += value(lm[j], k->ctrl_shift) / two_p * g_q(j, 0);
  }
  k->bias_gain = mantissa(1 + sum_h, k->ctrl_shift);
  k->ff_gain = mantissa((1 + sum_h + lg) / gain_q * two_p, k->ctrl_shift);

  const double fan = fan_loss_per_k * pow2(16 + p) / (255.0 * 256.0);
  if (!quantize_row(&fan, 1, 46, &k->fan_gain, &k->fan_shift)) return "fan gain out of range";
  double share[control::kSfMaxStates];
  for (int j = 0; j < n; ++j) share[j] = g_q(j, 0) / gain_q;
  if (!quantize_row(share, n, 46, k->ss_share, &k->ss_share_shift))
    return "steady state out of range";
  const double inv = two_p / gain_q;
  if (!quantize_row(&inv, 1, 46, &k->inv_gain, &k->inv_gain_shift)) return "DC gain out of range";
  return control::state_feedback_constants_valid(*k) ? nullptr : "constants fail the runtime's range checks";
}

// The whole chain for a model: the design with its default pole rule, quantised with the model's
// own fan loss. What `hotend-design` and the simulator upload with M311. nullptr on success.
inline const char* design_constants(const LtiModel& model, control::StateFeedbackConstants* k) {
  return quantize(design_state_feedback(model), model.fan_loss_per_k, k);
}

}  // namespace design
