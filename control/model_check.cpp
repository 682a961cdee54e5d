#include "control/model_check.h"

#include "control/fixed.h"

namespace control {
namespace {

constexpr int32_t kAmbientLowQ8 = 18L * 256;   // the lower bound's ambient (most loss)
constexpr int32_t kAmbientHighQ8 = 35L * 256;  // the upper bound's (least loss, e.g. an enclosure)
constexpr int32_t kLossLowQ12 = 4506;          // 1 + l = 1.1
constexpr int32_t kLossHighQ12 = 3686;         // 1 − l = 0.9
constexpr uint8_t kDrivenDuty = 128;           // default model: "driven" = ≥ 50 % over the window
constexpr uint8_t kOffDuty = 5;                // default model: "off" = ≤ 2 % over the window
constexpr uint8_t kPersistPeriods = 4;         // 0.5 s: longer than the range guard's 3 readings
constexpr uint8_t kLeakShift = 9;              // evidence forgets with τ = 512 periods (65.5 s at 128 ms)

}  // namespace

void ModelCheck::configure(const HotendModel& model, bool tuned, int32_t threshold_q8, uint16_t period_ms) {
  tuned_ = tuned;
  threshold_q16_ = threshold_q8 << 8;  // ≤ 255 °C: 2^24
  // h/C in Q22: period_ms·256·2^22 / (1000·C_q8) ≤ 2^23 for C ≥ 1 s; normalised to a 16-bit
  // mantissa so that one mul_q16 applies it (bound_q16).
  uint32_t rate = fixed::mul_div_u32(uint32_t{period_ms} * 256u, 1UL << 22, 1000UL * uint32_t(model.time_constant_q8));
  int8_t exp = 0;
  while (rate >= 65536u) rate >>= 1, --exp;
  while (rate != 0 && rate < 32768u) rate <<= 1, ++exp;
  rate_mantissa_ = static_cast<uint16_t>(rate);
  rate_shift_ = static_cast<int8_t>(2 - exp);  // net_q8·h/C·2^16 = mul_q16(net_q8, m)·2^(2 − exp)
  // A·(1 ∓ g), g = 15 %, × 16: A ≤ 2000 °C gives ≤ 36,800.
  heat_lo_q4_ = static_cast<uint16_t>(uint32_t(model.rise_q8) * 17u / 320u);
  heat_hi_q4_ = static_cast<uint16_t>(uint32_t(model.rise_q8) * 23u / 320u);
  // 1.1·F/100/255 per fan unit, Q16: F_q8·1.1·65536/6,528,000 ≤ 1,414 (F ≤ 500 %).
  fan_slope_q16_ = static_cast<uint16_t>(fixed::mul_div_u32(uint32_t(model.fan_loss_pct_q8), 72090u, 6528000u));
  allow_fall_q16_ = fixed::mul_div_u32(period_ms, 65536u / 4u, 1000u);   // 0.25 °C/s
  allow_rise_q16_ = fixed::mul_div_u32(period_ms, 65536u / 10u, 1000u);  // 0.1 °C/s
  // The dead-time window, in periods.
  const uint32_t dead = fixed::mul_div_u32(uint32_t(model.dead_time_q8), 1000u, 256u * period_ms);
  uint32_t first, last;
  if (tuned) {
    first = dead / 2;
    last = dead * 2 + 1000u / period_ms;
  } else {
    first = 0;
    last = dead * 3 + 30000u / period_ms;
  }
  bin_periods_ = static_cast<uint16_t>((last + kBins - 2) / (kBins - 1));
  if (bin_periods_ == 0) bin_periods_ = 1;
  const uint32_t first_bin = first / bin_periods_;
  first_bin_ = static_cast<uint8_t>(first_bin < kBins - 1 ? first_bin : kBins - 1);
  reset();
}

// noinline: LTO inlined it into more than one caller (90 B of AVR flash as a call).
__attribute__((noinline)) void ModelCheck::reset() {
  for (uint8_t i = 0; i < kBins; ++i) {
    min_[i] = 0;
    max_[i] = 255;
    fan_max_[i] = 255;
  }
  window_fan_ = 255;
  in_bin_ = 0;
  window_min_ = 0;
  window_max_ = 255;
  have_last_ = false;
  low_q16_ = 0;
  high_q16_ = 0;
  persist_ = 0;
}

void ModelCheck::close_bin() {
  head_ = (head_ + 1) & (kBins - 1);
  min_[head_] = 255;
  max_[head_] = 0;
  fan_max_[head_] = 0;
  in_bin_ = 0;
  uint8_t lo = 255, hi = 0, fan = 0;
  for (uint8_t age = 1; age < kBins; ++age) {
    const uint8_t i = (head_ - age) & (kBins - 1);
    if (fan_max_[i] > fan) fan = fan_max_[i];
  }
  window_fan_ = fan;
  for (uint8_t age = first_bin_ == 0 ? 1 : first_bin_; age < kBins; ++age) {
    const uint8_t i = (head_ - age) & (kBins - 1);
    if (min_[i] < lo) lo = min_[i];
    if (max_[i] > hi) hi = max_[i];
  }
  window_min_ = lo;
  window_max_ = hi;
}

// noinline: LTO inlined it into more than one caller (64 B of AVR flash as a call).
__attribute__((noinline)) int32_t ModelCheck::bound_q16(int32_t net_q8) const {
  const int32_t scaled = fixed::mul_q16(net_q8, rate_mantissa_);  // |net_q8| ≤ 2^21: ≤ 2^21
  return rate_shift_ >= 0 ? scaled << rate_shift_ : scaled >> -rate_shift_;  // shift ≤ 6: ≤ 2^27
}

ModelCheck::Verdict ModelCheck::step(int32_t temp_q8, uint16_t duty_q16, uint8_t fan_duty) {
  const uint8_t u = static_cast<uint8_t>(duty_q16 >> 8);
  if (u < min_[head_]) min_[head_] = u;
  if (u > max_[head_]) max_[head_] = u;
  if (fan_duty > fan_max_[head_]) fan_max_[head_] = fan_duty;
  const uint8_t fan = fan_max_[head_] > window_fan_ ? fan_max_[head_] : window_fan_;
  uint8_t u_lo = window_min_, u_hi = window_max_;
  if (first_bin_ == 0) {
    if (min_[head_] < u_lo) u_lo = min_[head_];
    if (max_[head_] > u_hi) u_hi = max_[head_];
  }
  if (++in_bin_ >= bin_periods_) close_bin();

  if (!have_last_) {
    last_temp_q8_ = temp_q8;
    have_last_ = true;
    return Verdict::kOk;
  }
  // Readings are within MINTEMP..MAXTEMP (the range guard): |ΔT| < 2^17, ×256 < 2^25.
  const int32_t rise_q16 = (temp_q8 - last_temp_q8_) * 256;
  last_temp_q8_ = temp_q8;
  int32_t low_step = 0, high_step = 0;
  if (tuned_) {
    // Heat in: A·(1∓g) (≤ 2500 °C, Q4) × duty (Q8) → Q12 → Q8. Loss: (T − ambient) × factor;
    // |T − ambient|·16 < 2^21 and the factor (Q12) < 2^15, so mul_q16 stays in range.
    const int32_t heat_lo_q8 = static_cast<int32_t>(fixed::mul_u16(heat_lo_q4_, u_lo) >> 4);
    const uint16_t loss_lo_q12 = static_cast<uint16_t>(kLossLowQ12 + (fixed::mul_u16(fan, fan_slope_q16_) >> 4));
    // (T − ambient) in °C × 16 fits int16 (readings are within MINTEMP..MAXTEMP): one 16×16
    // multiply, Q4 × Q12 = Q16 → Q8.
    const int16_t over_lo_q4 = static_cast<int16_t>((temp_q8 - kAmbientLowQ8) >> 4);
    const int32_t loss_lo_q8 = fixed::mul_i16_u16(over_lo_q4, loss_lo_q12) >> 8;
    low_step = rise_q16 - bound_q16(heat_lo_q8 - loss_lo_q8);
    const int32_t heat_hi_q8 = static_cast<int32_t>(fixed::mul_u16(heat_hi_q4_, u_hi) >> 4);
    const int16_t over_hi_q4 = static_cast<int16_t>((temp_q8 - kAmbientHighQ8) >> 4);
    const int32_t loss_hi_q8 = fixed::mul_i16_u16(over_hi_q4, kLossHighQ12) >> 8;
    high_step = rise_q16 - bound_q16(heat_hi_q8 - loss_hi_q8);
  } else {
    if (u_lo >= kDrivenDuty) low_step = rise_q16 + static_cast<int32_t>(allow_fall_q16_);
    if (u_hi <= kOffDuty) high_step = rise_q16 - static_cast<int32_t>(allow_rise_q16_);
  }
  // Leaky one-sided sums: |E| ≤ threshold + one step before a trip, far inside int32.
  low_q16_ = low_q16_ - (low_q16_ >> kLeakShift) + low_step;
  if (low_q16_ > 0) low_q16_ = 0;
  high_q16_ = high_q16_ - (high_q16_ >> kLeakShift) + high_step;
  if (high_q16_ < 0) high_q16_ = 0;
  // The high side gets twice the threshold: a sensor behind a lag (not a dead time) keeps rising
  // after the window once the heater is off (two-node hotend80w: 2.4 °C of evidence, host test).
  Verdict verdict = Verdict::kOk;
  if (low_q16_ < -threshold_q16_) verdict = Verdict::kHeatsTooLittle;
  if (high_q16_ > 2 * threshold_q16_) verdict = Verdict::kHeatsTooMuch;
  // Over the threshold for kPersistPeriods in a row: a thermistor that opens or shorts jumps in
  // one period and must be reported by the range guard (MINTEMP/MAXTEMP, 3 readings) instead.
  persist_ = verdict == Verdict::kOk ? 0 : (persist_ < kPersistPeriods ? persist_ + 1 : persist_);
  return persist_ >= kPersistPeriods ? verdict : Verdict::kOk;
}

}  // namespace control
