#include "firmware/thermal_watch.h"

namespace firmware {

void ThermalWatch::reset() {
  periods_ = 0;
  reached_ = false;
  target_q8_ = 0;
}

Fault ThermalWatch::update(int32_t target_q8, int32_t temp_q8, uint16_t duty_q16) {
  if (target_q8 != target_q8_) {  // a new target: "reached" starts over, the window runs on
    reached_ = false;
    target_q8_ = target_q8;
  }
  const int32_t error_q8 = target_q8 - temp_q8;
  if (target_q8 != 0 && error_q8 <= kReachedQ8) reached_ = true;
  if (target_q8 == 0 || duty_q16 < kMinDutyQ16) {  // off, or not driven hard: nothing to require
    periods_ = 0;
    return Fault::kNone;
  }
  if (periods_ == 0) {
    window_start_q8_ = temp_q8;
    far_ = error_q8 > kBandQ8;
  }
  if (++periods_ < window_periods_) return Fault::kNone;
  periods_ = 0;  // the next window starts with the next period
  const int32_t rise_q8 = temp_q8 - window_start_q8_;
  // Near the target: a fall counts only if it ends far below (a part-fan dip on a hotend with a
  // long dead time falls tens of degrees and recovers; hotend-sim's 2-hour print-like run on seed002).
  const bool fell = rise_q8 < -kMaxFallQ8 && error_q8 > kBandQ8;
  if (far_ ? rise_q8 < kMinRiseQ8 : fell) return reached_ ? Fault::kRunaway : Fault::kHeatingFailed;
  return Fault::kNone;
}

}  // namespace firmware
