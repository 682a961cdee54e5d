#include "firmware/heater_manager.h"

#include "hal/heater_pwm.h"

namespace firmware {

// noinline: LTO inlined it into more than one caller (58 B of AVR flash as a call).
__attribute__((noinline)) const gcode::FlashText* HeaterManager::set_target_q8(int32_t target_q8) {
  if (fault_ != Fault::kNone) return GCODE_TEXT("Heater fault latched, send M999 to clear");
  if (target_q8 == 0 && target_q8_ != 0) {
    switch_off();
    hal::heater_pwm::set_duty_q16(0);  // off from the next PWM period, not a full step later
  }
  target_q8_ = target_q8;
  return nullptr;
}

uint16_t HeaterManager::step(int32_t measured_q8, uint8_t fan_duty) {
  if (fault_ != Fault::kNone || target_q8_ == 0) {
    duty_q16_ = 0;
  } else {
    duty_q16_ = controller_->step(control::StepInput{target_q8_, measured_q8, fan_duty});
  }
  return duty_q16_;
}

uint16_t HeaterManager::hold(uint16_t duty_q16) {
  duty_q16_ = (fault_ != Fault::kNone || target_q8_ == 0) ? 0 : duty_q16;
  return duty_q16_;
}

uint16_t HeaterManager::hold_off() {
  hal::heater_pwm::force_off();
  duty_q16_ = 0;
  return 0;
}

// noinline: LTO inlined it into more than one caller (44 B of AVR flash as a call).
__attribute__((noinline)) bool HeaterManager::trip(Fault fault) {
  hal::heater_pwm::force_off();  // first: the pin is low before anything else happens
  target_q8_ = 0;
  switch_off();
  if (fault_ != Fault::kNone) return false;
  fault_ = fault;
  return true;
}

void HeaterManager::switch_off() {
  duty_q16_ = 0;
  controller_->reset();
}

}  // namespace firmware
