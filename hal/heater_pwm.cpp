#include "hal/heater_pwm.h"

#include "hal/board.h"
#include "hal/critical_section.h"
#include "hal/gpio.h"

namespace {

volatile uint16_t g_next_duty_q16;  // written by the main loop, latched at period start
uint16_t g_carry_q16;               // ISR: remainder below one tick, 0..511
volatile uint8_t g_on_ticks;        // ticks the pin is high in the running period, 0..128

}  // namespace

namespace hal {
namespace heater_pwm {

void set_duty_q16(uint16_t duty_q16) {
  CriticalSection lock;  // 16-bit store read by the ISR
  g_next_duty_q16 = duty_q16;
}

void force_off() {
  CriticalSection lock;
  g_next_duty_q16 = 0;
  g_on_ticks = 0;
  g_carry_q16 = 0;
  gpio::write(board::kHotendHeater, false);
}

// Cycle budget ~40 at a period start, ~15 otherwise. 16-bit arithmetic only: the duty is
// split so carry + remainder never exceeds 1023 and nothing overflows.
void on_tick(uint8_t phase) {
  const uint8_t tick_in_period = static_cast<uint8_t>(phase - kPeriodStartPhase) & (kPeriodTicks - 1);
  if (tick_in_period == 0) {
    const uint16_t duty_q16 = g_next_duty_q16;
    const uint16_t sum = static_cast<uint16_t>(g_carry_q16 + (duty_q16 & 0x1FF));
    g_on_ticks = static_cast<uint8_t>((duty_q16 >> 9) + (sum >> 9));
    g_carry_q16 = sum & 0x1FF;
  }
  // Written every tick (not only on edges): a disturbed pin state heals within 1 ms.
  gpio::write(board::kHotendHeater, tick_in_period < g_on_ticks);
}

}  // namespace heater_pwm
}  // namespace hal
