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
  temp_q8_ = sensor::adc_q6_to_temp_q8(adc_q6);
  Fault fault = guard_.update(adc_q6, temp_q8_);
  if (fault == Fault::kNone && !guard_.reading_bad()) fault = watch_.update(heater_.target_q8(), temp_q8_, heater_.duty_q16());
  bool newly_latched = false;
  uint16_t duty_q16;
  if (fault != Fault::kNone) {
    newly_latched = heater_.trip(fault);
    tune_.stop(AutotuneJob::Stop::kFault);
    duty_q16 = 0;
  } else if (guard_.reading_bad()) {
    duty_q16 = heater_.hold_off();
  } else if (tune_.busy()) {
    uint8_t fan_duty = 0;
    duty_q16 = heater_.hold(tune_.step(temp_q8_, &fan_duty));
    hal::fan_pwm::set_duty(fan_duty);
  } else {
    duty_q16 = heater_.step(temp_q8_, hal::fan_pwm::duty());
  }
  hal::heater_pwm::set_duty_q16(duty_q16);
  hal::step_marker::end();

  // The watchdog is kicked here and only here: if control periods stop, the board resets.
  hal::watchdog::kick();
  if (newly_latched) out_.error_line(fault_message(fault));  // the watch resets itself: target is 0
}

}  // namespace firmware
