// Part fan: first-order sigma-delta from the 1 kHz tick. Each tick adds the 8-bit duty to an
// accumulator and switches the fan on when it reaches 255, so the average on-fraction is
// exactly duty / 255 (255 = always on) with edges spread as evenly as possible.
#pragma once
#include <stdint.h>

namespace hal {
namespace fan_pwm {

void set_duty(uint8_t duty);  // 0..255; takes effect on the next tick
uint8_t duty();

// Tick ISR only.
void on_tick();

}  // namespace fan_pwm
}  // namespace hal
