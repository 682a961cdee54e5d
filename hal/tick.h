// The 1 kHz time base: Timer0 in CTC mode, 16 MHz / 64 / (249 + 1) = 1000 Hz exactly.
// Its ISR samples the ADC, runs the heater soft PWM and the fan sigma-delta, and counts time.
#pragma once
#include <stdint.h>

namespace hal {
namespace tick {

constexpr uint16_t kHz = 1000;

// Starts Timer0; adc::init must have run (the first tick reads a conversion).
void init();

// Milliseconds since init (wraps after 49.7 days; compare with unsigned differences).
uint32_t millis();

}  // namespace tick
}  // namespace hal
