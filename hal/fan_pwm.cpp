#include "hal/fan_pwm.h"

#include "hal/board.h"
#include "hal/gpio.h"

namespace {

volatile uint8_t g_duty;  // 0..255, single byte: no lock needed
uint16_t g_accumulator;   // ISR only, 0..254 between ticks

}  // namespace

namespace hal {
namespace fan_pwm {

void set_duty(uint8_t duty) { g_duty = duty; }
uint8_t duty() { return g_duty; }

// Cycle budget ~25 (+ ~6 for the port H read-modify-write on RAMPS).
void on_tick() {
  g_accumulator = static_cast<uint16_t>(g_accumulator + g_duty);
  const bool on = g_accumulator >= 255;
  if (on) g_accumulator = static_cast<uint16_t>(g_accumulator - 255);
  gpio::write(board::kPartFan, on);
}

}  // namespace fan_pwm
}  // namespace hal
