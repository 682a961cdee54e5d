#include "firmware/control_loop.h"

#include "firmware/temperature_sensor.h"
#include "hal/fan_pwm.h"
#include "hal/heater_pwm.h"
#include "hal/step_marker.h"
#include "hal/watchdog.h"

namespace firmware {

// noinline: inlined into main() (its only caller) the step shared main's register pressure
// and spilled inside the thermistor search; on its own it measured 1,400 instead of 1,800
// cycles (ATmega2560, simavr), for ~40 bytes of flash.
__attribute__((noinline)) void ControlLoop::run(uint16_t adc_q6) {
  hal::step_marker::begin();
  const uint16_t ran_q16 = heater_.duty_q16();  // the duty of the period that just ended
  temp_q8_ = sensor::adc_q6_to_temp_q8(adc_q6);
  Fault fault = guard_.update(adc_q6, temp_q8_);
  const bool plausible = fault == Fault::kNone && !guard_.reading_bad();
  bool newly_latched = false;
  uint16_t duty_q16;
  if (fault != Fault::kNone) {
    newly_latched = latch(fault);
    duty_q16 = 0;
  } else if (guard_.reading_bad()) {
    duty_q16 = heater_.hold_off();
  } else if (tune_.busy()) {
    uint8_t fan_duty = 0;
    duty_q16 = heater_.hold(tune_.step(temp_q8_, &fan_duty));
    hal::fan_pwm::set_duty(fan_duty);
  } else {
    duty_q16 = heater_.step(temp_q8_, airflow_.airflow());  // the fan feedforward follows the airflow
  }
  hal::heater_pwm::set_duty_q16(duty_q16);
  hal::step_marker::end();

  // The watchdog is kicked here and only here: if control periods stop, the board resets.
  hal::watchdog::kick();
  // The heating watch and the model check run after the duty is out, outside the timed step
  // (the check inside it measured +1,220 cycles mean, +1,600 max: pid+ff, ATmega2560, simavr;
  // the watch took the 5-state state feedback's step with a fan step to 3,001 cycles); a fault
  // either finds switches the heater off in this same period (HeaterManager::trip forces the pin
  // low first). Both see the duty that ran (M303's too); the check runs with the heater off as
  // well: a heater stuck on is found with no target set.
  if (plausible && !newly_latched) {
    fault = watch_.update(heater_.target_q8(), temp_q8_, ran_q16);
    if (fault == Fault::kNone) {
      const control::ModelCheck::Verdict verdict = check_.step(temp_q8_, ran_q16, airflow_.airflow());
      if (verdict == control::ModelCheck::Verdict::kHeatsTooMuch) {
        fault = Fault::kStuckOn;
      } else if (verdict == control::ModelCheck::Verdict::kHeatsTooLittle) {
        fault = watch_.reached() ? Fault::kModelRunaway : Fault::kModelHeatingFailed;
      }
    }
    if (fault != Fault::kNone) {
      newly_latched = latch(fault);
      // A heater stuck on cannot be switched off: say so even when another fault is latched.
      if (fault == Fault::kStuckOn && !stuck_reported_) newly_latched = true;
      if (fault == Fault::kStuckOn) stuck_reported_ = true;
    }
  }
  // The hold's K for a later M303 (outside the timed step; one division every 65 s). A tune's
  // own duty is no hold, and a tune ends with K from its relay: the hold's is then forgotten.
  if (tune_.busy()) {
    hold_.reset();
  } else if (plausible) {
    hold_.update(heater_.target_q8(), temp_q8_, ran_q16, hal::fan_pwm::duty());
  }
  if (newly_latched) unreported_ = static_cast<uint16_t>(unreported_ | (1u << static_cast<uint8_t>(fault)));
  // Outside the timed step (the 5-state state feedback's has little to spare): the next
  // period's airflow, with the duty the pin has now (M106 before then retargets it).
  airflow_.step(hal::fan_pwm::duty());
}

// noinline: LTO inlined it into both of the machine's callers (M106/M107 and the tune's end).
__attribute__((noinline)) void ControlLoop::set_fan_duty(uint8_t duty) {
  hal::fan_pwm::set_duty(duty);
  airflow_.retarget(duty);
}

bool ControlLoop::latch(Fault fault) {
  const bool newly = heater_.trip(fault);
  tune_.stop(AutotuneJob::Stop::kFault);
  return newly;
}

void ControlLoop::report(gcode::Output& out) {
  const uint16_t faults = unreported_;
  unreported_ = 0;  // first: a step inside these writes may latch another (printed next pass)
  for (uint8_t f = 1; faults >> f != 0; ++f) {
    if ((faults >> f & 1u) == 0) continue;
    const Fault fault = static_cast<Fault>(f);
    out.error_line(fault_message(fault));
    const gcode::FlashText* reason = fault_reason(fault);
    if (reason != nullptr) out.error_line(reason);
  }
}

void ControlLoop::sync_protection(const Settings& s) {
  const bool tight = s.model_tuned == kModelMeasured;
  const uint8_t threshold_c = tight ? s.protect_tuned_c : s.protect_default_c;
  watch_.set_window_periods(static_cast<uint16_t>(uint32_t{s.watch_period_s} * 1000u / kControlPeriodMs));
  const control::HotendModel& m = s.model;
  if (check_tuned_ == s.model_tuned && check_threshold_c_ == threshold_c && control::same_model(m, check_model_)) return;
  check_.configure(m, tight, int32_t{threshold_c} << 8, kControlPeriodMs);
  check_model_ = m;
  check_tuned_ = s.model_tuned;
  check_threshold_c_ = threshold_c;
}

void ControlLoop::restart_protection() {
  stuck_reported_ = false;
  check_.reset();
  watch_.reset();
}

}  // namespace firmware
