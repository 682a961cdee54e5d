// Fixed-point state feedback (see state_feedback.h). Arithmetic notes:
// - every product is int16 mantissa × int32 signal rounded to 32 bits (state_feedback_math.h);
//   a row is summed at its own exponent and shifted once (no 64-bit arithmetic, no division);
// - signals are clamped to ±2^27 (and intermediate sums stay below 2^28), so a row of <= 7
//   products cannot overflow int32;
// - the time update carries the bits it shifts out (residual_) into the next period: slow poles
//   (1 − λ ≈ 1e-4) would otherwise park the state anywhere in a ±0.5 LSB/(1 − λ) dead band;
// - `>>` on negative int32 is arithmetic (floor) with gcc and avr-gcc, which the rounding uses.
#include "control/state_feedback.h"

#include "control/state_feedback_math.h"

namespace control {
namespace {

using sf::mulhi16;       // round(m·x / 2^16), inlined: the time update (the longest call)
using sf::mulhi16_call;  // the same product as a call: every other one

constexpr int32_t kSignalLimit = int32_t(1) << 27;  // ±2048 °C in Q16

// |v| <= limit; the common in-range case costs one add and one unsigned compare.
inline int32_t clamp_abs(int32_t v, int32_t limit) {
  if (static_cast<uint32_t>(v) + static_cast<uint32_t>(limit) <= 2 * static_cast<uint32_t>(limit))
    return v;
  return v < 0 ? -limit : limit;
}

// 2^sh (0 <= sh <= 31) and arithmetic shift right: whole bytes first (register moves on AVR),
// then at most 7 single-bit steps. The design picks byte-aligned exponents for the observer
// gains (the busiest call), so those shifts are register moves. pow2 shifts the bit within a
// byte (8-bit steps are cheap on AVR) and then moves bytes: no 32-bit shift loop.
inline uint32_t pow2(uint8_t sh) {
  uint32_t v = static_cast<uint8_t>(1u << (sh & 7));
  if (sh & 16) v <<= 16;
  if (sh & 8) v <<= 8;
  return v;
}

inline int32_t asr(int32_t v, uint8_t sh) {
  if (sh > 31) sh = 31;
  if (sh >= 16) {
    v >>= 16;
    sh -= 16;
  }
  if (sh >= 8) {
    v >>= 8;
    sh -= 8;
  }
  while (sh--) v >>= 1;
  return v;
}

// v·2^n saturating at ±2^28 (bytes first): the law's terms M·r and L·x can each be hundreds
// of times full power before they cancel.
inline int32_t shl_sat(int32_t v, uint8_t n) {
  constexpr int32_t kLimit = int32_t(1) << 28;
  for (; n >= 8; n -= 8) {
    if (v >= (kLimit >> 8) || v <= -(kLimit >> 8)) return v < 0 ? -kLimit : kLimit;
    v *= 256;
  }
  for (; n != 0; --n) {
    if (v >= (kLimit >> 1) || v <= -(kLimit >> 1)) return v < 0 ? -kLimit : kLimit;
    v *= 2;
  }
  return v;
}

// v·2^−sh: rounded half up for sh > 0, saturating shl_sat for sh <= 0. The rounding is
// floor((floor(v / 2^(sh−1)) + 1) / 2) = floor((v + 2^(sh−1)) / 2^sh): no 2^sh to build, and
// no overflow for any v.
inline int32_t scale(int32_t v, int8_t sh) {
  if (sh > 0) return (asr(v, static_cast<uint8_t>(sh - 1)) + 1) >> 1;
  return shl_sat(v, static_cast<uint8_t>(-sh));
}

// Signed duty Q15 (the history) · 2^(p+1) (p <= 10, no overflow): the duty as a Q(16+p) signal.
inline int32_t duty_signal(int16_t duty_q15, uint8_t p) {
  int32_t v = duty_q15;
  ++p;
  if (p >= 8) {
    v *= 256;
    p -= 8;
  }
  while (p--) v *= 2;
  return v;
}

// Mantissa exponents are stored as shifts from the Q16 product (value = m / 2^shift).
inline int8_t exponent(uint8_t shift) { return static_cast<int8_t>(shift) - 16; }

inline int32_t to_q16(int32_t temp_q8) { return clamp_abs(temp_q8, kSignalLimit >> 8) * 256; }

}  // namespace

bool StateFeedback::configure(const StateFeedbackConstants& k) {
  if (!state_feedback_constants_valid(k)) return false;
  k_ = k;
  follows_fan_ = k.decimation > state_feedback_min_decimation(k.delay);
  configured_ = true;
  reset();
  return true;
}

void StateFeedback::reset() {
  primed_ = false;
  phase_ = 0;
  duty_q16_ = 0;
}

void StateFeedback::init_bumpless(int32_t measured_q8, uint16_t duty_q16) {
  if (configured_) prime(measured_q8, duty_q16, false);
}

// Observer at the steady state of the measured temperature under `duty_q16`; after reset the
// bias is zeroed instead (the heater was off: the plant is assumed to be cooling freely).
void StateFeedback::prime(int32_t measured_q8, uint16_t duty_q16, bool zero_bias) {
  const int32_t rise = to_q16(measured_q8 - k_.ambient_q8);
  for (uint8_t i = 0; i < k_.n; ++i) {
    x_q16_[i] = scale(mulhi16_call(k_.ss_share[i], rise), exponent(k_.ss_share_shift));
    residual_[i] = 0;
  }
  const int32_t v = scale(mulhi16_call(k_.inv_gain, rise), exponent(k_.inv_gain_shift));
  const int32_t u = duty_signal(static_cast<int16_t>(duty_q16 >> 1), k_.input_shift);
  bias_ = zero_bias ? 0 : clamp_abs(v - u, static_cast<int32_t>(pow2(16 + k_.input_shift)));
  const int16_t duty_q15 = static_cast<int16_t>(duty_q16 >> 1);
  for (uint8_t j = 0; j <= kSfMaxDelay; ++j) hist_[j] = duty_q15;
  head_ = 0;
  duty_q16_ = duty_q16;
  // Until the first law update the primed duty holds, the fan's share in it (follow_fan adds 0).
  net_q16_ = duty_q16;
  rise_q8_ = 0;
  fan_full_q16_ = 0;
  phase_ = k_.delay > 0 ? 2 : 0;  // predictor sum first (its chunks), then the first law update
  primed_ = true;
}

int16_t StateFeedback::history(uint8_t j) const {
  const uint8_t idx = head_ >= j ? head_ - j : head_ + (kSfMaxDelay + 1) - j;
  return hist_[idx];
}

uint16_t StateFeedback::step(const StepInput& in) {
  if (!configured_) return 0;
  if (!primed_) {  // a call of its own, so no call does priming and a law update
    prime(in.measured_q8, 0, true);
    return duty_q16_;
  }
  const uint8_t phase = phase_;
  phase_ = phase + 1 >= k_.decimation ? 0 : phase + 1;
  if (phase == 0) {
    law_update(in);
  } else if (phase == 1) {
    time_update();
  } else if (static_cast<uint8_t>(phase - 2) * kSfFirChunk < k_.delay) {
    fir_chunk(phase - 2);
  } else {
    // A call with nothing else to do: the fan's share follows the airflow between law updates
    // (a law period is up to 32 s; a fan step held back that long came back as a dip one dead
    // time later), and its full-airflow value is computed here, off the law update's cycles.
    fan_full_q16_ = static_cast<uint16_t>(fan_share(rise_q8_, 255));
    if (in.fan_duty != fan_seen_) follow_fan(in.fan_duty);
  }
  return duty_q16_;  // the law's part held for the whole law period (ZOH at decimation × 128 ms)
}

// Known part-fan loss gain·fan·rise in duty Q16 (0..65535): rise_q8 < 2^19 (y is clamped to
// ±2^27 in Q16), × fan ≤ 255 < 2^27 for mulhi16.
__attribute__((always_inline)) inline int32_t StateFeedback::fan_share(int32_t rise_q8, uint8_t fan_duty) const {
  if (k_.fan_gain == 0 || fan_duty == 0 || rise_q8 <= 0) return 0;
  const int32_t q16 = scale(mulhi16_call(k_.fan_gain, rise_q8 * fan_duty),
                            static_cast<int8_t>(exponent(k_.fan_shift) + k_.input_shift));
  return q16 < 0 ? 0 : (q16 > 65535 ? 65535 : q16);
}

__attribute__((noinline)) int32_t StateFeedback::follow_fan(uint8_t fan_duty) {
  fan_seen_ = fan_duty;
  // fan_full·fan·257/2^16 = fan_full·fan/255: both factors < 2^16, the product fits 32 bits;
  // |net| ≤ 2^27, so the sum fits int32.
  const int32_t fan_q16 =
      static_cast<int32_t>((static_cast<uint32_t>(fan_full_q16_) * static_cast<uint16_t>(fan_duty * 257u) + 32768u) >> 16);
  const int32_t applied = net_q16_ + fan_q16;
  duty_q16_ = static_cast<uint16_t>(applied < 0 ? 0 : (applied > 65535 ? 65535 : applied));
  return fan_q16;
}

void StateFeedback::law_update(const StepInput& in) {
  const uint8_t n = k_.n;
  int32_t* x = x_q16_;
  // Measurement update.
  const int32_t y = to_q16(in.measured_q8 - k_.ambient_q8);
  int32_t y_model = 0;
  uint8_t bit = 1;
  for (uint8_t j = 0; j < n; ++j, bit <<= 1)
    if (k_.output_mask & bit) y_model += x[j];
  const int32_t e = clamp_abs(y - y_model, kSignalLimit);
  const int16_t* gain = k_.obs_gain;
  const uint8_t* shift = k_.obs_shift;
  for (uint8_t i = 0; i < n; ++i)
    x[i] = clamp_abs(x[i] + scale(mulhi16_call(gain[i], e), exponent(shift[i])), kSignalLimit);
  bias_ = clamp_abs(bias_ + scale(mulhi16_call(gain[n], e), exponent(shift[n])),
                    static_cast<int32_t>(pow2(16 + k_.input_shift)));  // ±100 % duty
  // Law on the predicted state, in effective duty (heater minus the fan's loss), Q16:
  // M r − L_D x̂ − g_d d̂ − Σ h_j u_eff[k−j].
  const int32_t r = to_q16(in.target_q8 - k_.ambient_q8);
  int32_t acc = mulhi16_call(k_.ff_gain, r) - mulhi16_call(k_.bias_gain, bias_);
  for (uint8_t j = 0; j < n; ++j)
    if (k_.fb_gain[j] != 0) acc -= mulhi16_call(k_.fb_gain[j], x[j]);
  const int8_t p = static_cast<int8_t>(k_.input_shift);
  int32_t u = scale(acc, static_cast<int8_t>(exponent(k_.ctrl_shift) + p));
  if (k_.delay > 0)
    u -= scale(fir_, static_cast<int8_t>(static_cast<int8_t>(k_.fir_shift) + p - 9));
  u = clamp_abs(u, kSignalLimit);
  // Known part-fan loss added with weight 1: the fan's cooling reaches the sensor through the
  // same dead time as the heater, so the extra duty applied now cancels it as it arrives and the
  // loop (model, history, predictor) never sees the fan.
  int32_t fan_q16;
  int32_t applied;
  if (follows_fan_) {
    // Idle calls keep the share on the airflow between law updates, and compute its full-airflow
    // value from this rise, off this call's cycles (it is one law period old here).
    rise_q8_ = y >> 8;
    net_q16_ = u;
    fan_q16 = follow_fan(in.fan_duty);
    applied = duty_q16_;
  } else {
    // No idle call (a law period of at most 4 calls, 512 ms): the share is held with the law.
    // The 5-state seed000 design has ~10 cycles to spare here: no more work on this path.
    fan_q16 = fan_share(y >> 8, in.fan_duty);
    applied = u + fan_q16;
    applied = applied < 0 ? 0 : (applied > 65535 ? 65535 : applied);
    duty_q16_ = static_cast<uint16_t>(applied);
  }
  // The model's input is what the heater really did net of the fan: it is negative when the
  // heater is off with the fan on (history in signed Q15, ±100 %; floor keeps 65535 in range).
  head_ = head_ == kSfMaxDelay ? 0 : head_ + 1;
  hist_[head_] = static_cast<int16_t>((applied - fan_q16) >> 1);
}

// x̂[k+1] from x̂[k] and the applied duty: every row reads the old vector, so all deltas are
// formed before any state changes. The law call leaves |x| <= 2^27 and state_feedback_row_fits
// bounds each row's coefficients by 8, so |delta| <= 2^30 + 2^17 and x + delta fits int32; the
// clamp keeps the next law call's sum of states in int32 (derivation in
// state_feedback_constants.h).
void StateFeedback::time_update() {
  const uint8_t n = k_.n;
  const uint8_t p = k_.input_shift;
  const int32_t va = clamp_abs(duty_signal(history(k_.delay), p) + bias_, kSignalLimit);
  const int32_t vb =
      k_.delay > 0 ? clamp_abs(duty_signal(history(k_.delay - 1), p) + bias_, kSignalLimit) : va;
  int32_t delta[kSfMaxStates];
  for (uint8_t i = 0; i < n; ++i) {
    int32_t acc = mulhi16(k_.phi_diag[i], x_q16_[i]);
    if (k_.phi_off[i] != 0) acc += mulhi16(k_.phi_off[i], x_q16_[k_.phi_col[i]]);
    if (k_.gamma_a[i] != 0) acc += mulhi16(k_.gamma_a[i], va);
    if (k_.gamma_b[i] != 0) acc += mulhi16(k_.gamma_b[i], vb);
    const int8_t sh = exponent(k_.phi_shift[i]);
    if (sh > 0) {  // floor shift; the bits shifted out wait for the next period
      const int32_t t = acc + static_cast<int32_t>(residual_[i]);
      delta[i] = asr(t, static_cast<uint8_t>(sh));
      residual_[i] = static_cast<uint32_t>(t) & (pow2(static_cast<uint8_t>(sh)) - 1);
    } else {  // fast modes (|Φ − I| > ½): exact left shift, bounded as above
      uint32_t v = static_cast<uint32_t>(acc);
      for (int8_t k = sh; k < 0; ++k) v <<= 1;
      delta[i] = static_cast<int32_t>(v);
    }
  }
  for (uint8_t i = 0; i < n; ++i) x_q16_[i] = clamp_abs(x_q16_[i] + delta[i], kSignalLimit);
}

// Taps j = 16c+1 .. 16c+16 (<= D) of Σ h_j·u[k+1−j] for the next law update; u[k] is at head_.
// Products (mantissa × duty Q15) are pre-shifted by 8 so 32 of them fit in int32.
void StateFeedback::fir_chunk(uint8_t chunk) {
  if (chunk == 0) fir_ = 0;
  const uint8_t first = chunk * kSfFirChunk;  // tap index j − 1
  uint8_t count = k_.delay - first;
  if (count > kSfFirChunk) count = kSfFirChunk;
  const int16_t* h = &k_.fir[first];
  const int16_t* u = &hist_[head_ >= first ? head_ - first : head_ + (kSfMaxDelay + 1) - first];
  int32_t sum = fir_;
  for (; count != 0; --count) {
    sum += (static_cast<int32_t>(*h++) * static_cast<int32_t>(*u)) >> 8;
    u = u == hist_ ? &hist_[kSfMaxDelay] : u - 1;
  }
  fir_ = sum;
}

}  // namespace control
