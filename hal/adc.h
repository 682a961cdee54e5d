// Oversampled thermistor ADC. The tick ISR reads one conversion per millisecond and starts
// the next; 128 samples make one `adc_q6` value (mean 10-bit code x 64, 0..65472) per
// 128 ms control period, handed to the main loop with a flag.
#pragma once
#include <stdint.h>

namespace hal {
namespace adc {

constexpr uint8_t kSamplesPerWindow = 128;  // = control period in ticks (brief)

// AVcc reference, ADC clock 16 MHz / 128 = 125 kHz (inside the 50..200 kHz the datasheet asks
// for 10-bit accuracy; a conversion takes 13 clocks = 104 us, well inside one 1 ms tick).
// Selects `channel` (0..15; 8..15 only on the ATmega2560) and starts the first conversion.
void init(uint8_t channel);

// Tick ISR only: take the finished conversion, start the next, and publish the window's
// adc_q6 when `window_end` is true.
void on_tick(bool window_end);

// True when a finished window waits to be taken (cheap: for the sleep decision).
bool window_ready();

// Main loop: true once per window, with that window's adc_q6 (mean code x 64).
bool take_window(uint16_t& adc_q6);

}  // namespace adc
}  // namespace hal
