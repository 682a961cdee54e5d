// One control period (every 128 ms, when the tick ISR publishes a 128-sample ADC window):
// convert, range-check, control, hand the duty to the PWM -- bracketed by the GPIOR0 marker the
// simulator times -- then the heating watch and the model check. Faults found here are latched in
// the heater manager (the pin forced low at once) and reported.
#pragma once
#include <stdint.h>

#include "control/fan_airflow.h"
#include "control/model_check.h"
#include "control/steady_hold.h"
#include "firmware/controller_autotune.h"
#include "firmware/controller_settings.h"
#include "firmware/gcode_output.h"
#include "firmware/heater_manager.h"
#include "firmware/range_guard.h"
#include "firmware/thermal_watch.h"

namespace firmware {

class ControlLoop {
 public:
  // constexpr: constant-initialised (a start-up constructor storing its zeros cost ~450 B of flash).
  constexpr ControlLoop(HeaterManager& heater, AutotuneJob& tune) : heater_(heater), tune_(tune) {}

  // One period from the window's adc_q6 (mean ADC code x 64).
  void run(uint16_t adc_q6);
  // Prints the Error lines of a fault run() latched. Separate from run(): a step may run inside
  // a reply (hal::uart's TX wait hook), where its lines would split the reply's line.
  void report(gcode::Output& out);

  int32_t temp_q8() const { return temp_q8_; }  // latest conversion, degC x 256 (0 before the first)
  // The cause of a MINTEMP/MAXTEMP fault is still present (M999 must refuse).
  bool reading_bad() const { return guard_.reading_bad(); }
  Fault reading_fault() const { return guard_.last(); }
  // The protection follows the settings in force: the model check is reconfigured (set-up code,
  // two long divisions: call from the main loop, not the step) when the model, its origin or
  // M570 changed. Cheap when nothing changed.
  void sync_protection(const Settings& s);
  // M999: the model check and the watch start over.
  void restart_protection();
  // The part fan's pin, and the airflow the next period's controllers see (control/fan_airflow.h).
  void set_fan_duty(uint8_t duty);
  // The static gain of the last steady hold (control/steady_hold.h), for M303; 0 if none.
  int32_t hold_gain_q8() const { return hold_.static_gain_q8(); }

 private:
  // Latches `fault` (heater off at once) and ends an M303; false if a fault was already latched.
  bool latch(Fault fault);
  HeaterManager& heater_;
  AutotuneJob& tune_;  // while busy, M303 drives the heater and the part fan
  RangeGuard guard_;
  ThermalWatch watch_;
  control::ModelCheck check_;
  control::FanAirflow airflow_;  // the part fan's airflow, lagging its pin
  control::SteadyHold hold_;     // measured while a controller holds its target (not during M303)
  control::HotendModel check_model_{0, 0, 0, 0};  // what check_ was configured with
  uint8_t check_tuned_ = 0xFF;                    // 0xFF: never configured
  uint8_t check_threshold_c_ = 0;
  uint16_t unreported_ = 0;  // bit (1 << Fault) per fault run() latched and report() has not printed
  bool stuck_reported_ = false;  // kStuckOn printed (it is printed even over another latched fault)
  int32_t temp_q8_ = 0;
};

}  // namespace firmware
