// The model-free heating watch, the backstop behind the model check (control/model_check.h): it
// knows nothing about the hotend, so it is lenient, but it cannot be switched off by a target
// change or a target near the reading. A window runs while the heater is driven at ≥ 50 %
// (a period below restarts it: M303's baseline, cool-downs and dead-time waits hold the heater
// off for minutes on slow hotends, and then no rise can be required). At the window's end:
//   - far (> 10 °C) below the target when it began: the reading must have risen ≥ 2 °C;
//   - otherwise (near the target, any target): it must not have fallen more than 10 °C to end
//     more than 10 °C below the target (3 °C, or any 10 °C fall, tripped hotend-sim's print-like
//     runs on fopdt-delay25 and seed002: part-fan dips on hotends with a 20–25 s dead time).
// A new target keeps the running window. Marlin uses the same idea (WATCH_TEMP_PERIOD /
// INCREASE, THERMAL_PROTECTION_*) with 20 s / 2 °C for heating. The window defaults to 120 s
// (M570 P) because the simulator's seed000 models first dip (non-minimum phase) and rise only
// ~1.5 °C in their first 60 s under the PID (+9.9 / +12.7 °C at 120 s).
#pragma once
#include <stdint.h>

#include "firmware/fault.h"

namespace firmware {

class ThermalWatch {
 public:
  static constexpr int32_t kBandQ8 = 10L * 256;      // "far below target": 10 degC
  static constexpr int32_t kMinRiseQ8 = 2L * 256;    // required rise per window from far below: 2 degC
  static constexpr int32_t kMaxFallQ8 = 10L * 256;   // allowed fall per window near the target: 10 degC
  static constexpr int32_t kReachedQ8 = 2L * 256;    // within 2 degC counts as "target reached"
  static constexpr uint16_t kMinDutyQ16 = 32768;     // 50 %: "the heater is heating"

  // The window, in control periods (M570 P); takes effect with the next window.
  void set_window_periods(uint16_t periods) { window_periods_ = periods; }
  // Call once per control period with a plausible reading and the heater duty of the period it
  // ends. kHeatingFailed when the target has not been reached since it was last changed,
  // kRunaway when it had been; else kNone.
  Fault update(int32_t target_q8, int32_t temp_q8, uint16_t duty_q16);
  void reset();  // heater off / fault cleared: start over
  bool reached() const { return reached_; }  // the target was reached since it was set

 private:
  uint16_t window_periods_ = 938;  // 938 × 128 ms = 120.1 s
  int32_t window_start_q8_ = 0;    // temperature when the running window began
  uint16_t periods_ = 0;           // periods in the running window, 0 = no window running
  int32_t target_q8_ = 0;          // target `reached_` belongs to
  bool far_ = false;               // the running window began far below the target
  bool reached_ = false;
};

}  // namespace firmware
