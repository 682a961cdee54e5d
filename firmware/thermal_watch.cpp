#include "firmware/thermal_watch.h"

namespace firmware {

void ThermalWatch::reset() {
  periods_ = 0;
  reached_ = false;
  target_q8_ = 0;
}

Fault ThermalWatch::update(int32_t target_q8, int32_t temp_q8, uint16_t duty_q16) {
  if (target_q8 != target_q8_) {
    reset();
    target_q8_ = target_q8;
  }
  if (target_q8 == 0) return Fault::kNone;
  const int32_t error_q8 = target_q8 - temp_q8;
  if (error_q8 <= kReachedQ8) reached_ = true;
  if (error_q8 <= kBandQ8 || duty_q16 < kMinDutyQ16) {  // near or above target, or not heating
    periods_ = 0;
    return Fault::kNone;
  }
  if (periods_ == 0) window_start_q8_ = temp_q8;
  if (++periods_ < kWindowPeriods) return Fault::kNone;
  if (temp_q8 - window_start_q8_ < kMinRiseQ8) return reached_ ? Fault::kRunaway : Fault::kHeatingFailed;
  periods_ = 0;  // rose enough: watch the next window
  return Fault::kNone;
}

}  // namespace firmware
