// Hotend heater soft PWM driven from the 1 kHz tick: period 128 ticks (7.8 Hz, slow enough
// for a logic-level MOSFET switching a cartridge heater without switching loss or EMI).
// Per period on_ticks = (carry + duty_q16) >> 9 and the carry keeps the remainder, so the
// average power equals duty_q16 / 65536 exactly over time, with no division.
#pragma once
#include <stdint.h>

namespace hal {
namespace heater_pwm {

constexpr uint8_t kPeriodTicks = 128;

// Phase (tick 0..127 of the control period) at which a PWM period starts. The ADC window
// closes at phase 127, the main loop computes the new duty right after; starting the PWM
// period 4 ticks later leaves the main loop 4 ms to hand it over. A duty handed over later
// takes effect one period later (the previous duty runs once more).
constexpr uint8_t kPeriodStartPhase = 3;

// Duty (65535 = 100 %) for the next PWM period and the ones after.
void set_duty_q16(uint16_t duty_q16);

// Fault path: duty 0 from now on, the running period cut short, the pin low before return.
void force_off();

// Tick ISR only: `phase` is the tick number 0..127 in the control period.
void on_tick(uint8_t phase);

}  // namespace heater_pwm
}  // namespace hal
