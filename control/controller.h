// The one interface every hotend controller implements (PID, state feedback, fuzzy-PID, ...),
// so the heater manager can switch between them at run time. Portable, no AVR header.
#pragma once
#include <stdint.h>

namespace control {

// What a controller sees each control period.
struct StepInput {
  int32_t target_q8;    // set point, degC x 256 (0 = heater off; the manager never steps then)
  int32_t measured_q8;  // thermistor temperature, degC x 256
  uint8_t fan_duty;     // part-fan command 0..255, for fan feedforward
};

class Controller {
 public:
  // One control period; returns the heater duty for the next period (duty_q16, 65535 = 100 %).
  virtual uint16_t step(const StepInput& in) = 0;
  // Forget all history (used when the heater is switched off or a fault clears).
  virtual void reset() = 0;
  // Take over from another controller without a jump: start so that the next output is
  // close to duty_q16 at the current temperature.
  virtual void init_bumpless(int32_t measured_q8, uint16_t duty_q16) = 0;

 protected:
  ~Controller() = default;  // never deleted through this interface (no heap in the firmware)
};

}  // namespace control
