#include "control/steady_hold.h"

#include "control/autotune.h"

namespace control {

// K counts from the ambient a hot start's tune assumes: the two must be one figure.
static_assert(SteadyHold::kAmbientQ8 == Autotune::kDefaultAmbientQ8, "SteadyHold and Autotune count from one ambient");

void SteadyHold::update(int32_t target_q8, int32_t measured_q8, uint16_t duty_q16, uint8_t fan_duty) {
  const int32_t error_q8 = measured_q8 - target_q8;
  const int16_t target_q6 = static_cast<int16_t>(target_q8 >> 2);  // targets 0..~500 °C
  const bool holding = target_q8 > 0 && fan_duty == 0 && error_q8 <= kBandQ8 && error_q8 >= -kBandQ8;
  if (!holding || target_q6 != target_q6_) {
    // The window starts again (with this period if it holds the new target). A complete
    // window's K stays: it is the hotend's, whatever target or fan came after.
    target_q6_ = target_q6;
    sum_temp_q8_ = 0;
    sum_duty_ = 0;
    periods_ = 0;
    if (!holding) return;
  }
  sum_temp_q8_ += measured_q8;
  sum_duty_ += duty_q16;
  if (++periods_ < kWindowPeriods) return;
  // K = rise / duty, once per window (one division, ~65 s apart): rise_q8 · 2^8 / (duty_q16 / 2^4)
  // is °C × 16 per unit duty; the rise is within ±1 °C of a target ≤ 275 °C (< 2^17 in Q8, so
  // the numerator < 2^25), and the divisor ≥ kMinDutyQ16 / 16 = 81 (a 1.2 % step at most).
  const int32_t rise_q8 = (sum_temp_q8_ >> 9) - kAmbientQ8;  // ÷ kWindowPeriods
  const uint16_t duty_q16_mean = static_cast<uint16_t>(sum_duty_ >> 9);
  sum_temp_q8_ = 0;
  sum_duty_ = 0;
  periods_ = 0;
  if (duty_q16_mean < kMinDutyQ16 || rise_q8 <= 0) return;
  const uint32_t k_q4 = (static_cast<uint32_t>(rise_q8) << 8) / (duty_q16_mean >> 4);
  if (k_q4 >= kMinGainQ4 && k_q4 <= kMaxGainQ4) gain_q4_ = static_cast<uint16_t>(k_q4);
}

}  // namespace control
