// The hotend heater's state: target, the controller, the duty it asked for, and the latched
// fault. The controller is any control::Controller; the firmware passes the ControllerBank,
// which switches between the issue-3 controllers at run time without a bump in the duty.
#pragma once
#include <stdint.h>

#include "control/controller.h"
#include "firmware/fault.h"
#include "firmware/gcode_text.h"

namespace firmware {

class HeaterManager {
 public:
  explicit constexpr HeaterManager(control::Controller& controller) : controller_(&controller) {}

  // 0 = off (the heater stops at the next PWM period). Refused while a fault is latched.
  const gcode::FlashText* set_target_q8(int32_t target_q8);
  int32_t target_q8() const { return target_q8_; }

  // One control period with a plausible reading: returns the duty for the next PWM period.
  uint16_t step(int32_t measured_q8, uint8_t fan_duty);
  // One control period driven by a job that sets the duty itself (M303): the duty for the
  // next PWM period, 0 when the target is off or a fault is latched.
  uint16_t hold(uint16_t duty_q16);
  // One control period with a reading the range guard distrusts: heater off now, the
  // controller is not fed the bad value (it keeps its state: one glitch costs one period).
  uint16_t hold_off();

  // Latches `fault`: target 0, heater pin low before returning. False if a fault was
  // already latched (the first one stays, and is not reported twice).
  bool trip(Fault fault);
  Fault fault() const { return fault_; }
  void clear_fault() { fault_ = Fault::kNone; }  // the caller checked that the cause is gone

  uint16_t duty_q16() const { return duty_q16_; }  // last handed to the PWM, 65535 = 100 %

 private:
  void switch_off();

  control::Controller* controller_;
  int32_t target_q8_ = 0;  // degC x 256, 0 = off
  uint16_t duty_q16_ = 0;
  Fault fault_ = Fault::kNone;
};

}  // namespace firmware
