#include "hal/tick.h"

#include <avr/interrupt.h>
#include <avr/io.h>

#include "hal/adc.h"
#include "hal/critical_section.h"
#include "hal/fan_pwm.h"
#include "hal/heater_pwm.h"

namespace {

volatile uint32_t g_millis;
uint8_t g_phase;  // ISR only: tick number in the 128-tick control period

static_assert(hal::adc::kSamplesPerWindow == hal::heater_pwm::kPeriodTicks,
              "one ADC window per PWM period keeps their phase fixed");

// Whole ISR including entry/exit: measured in simavr at max 189 / mean 162 cycles on the
// ATmega2560 (port-H fan pin) and 179 / 152 on the ATmega1284P, i.e. ~1.2 % of the CPU at
// 1 kHz. Straight-line work on static data; the callees are inlined by LTO (one caller each).
inline void on_tick() {
  const uint8_t phase = g_phase;
  hal::adc::on_tick(phase == hal::adc::kSamplesPerWindow - 1);
  hal::heater_pwm::on_tick(phase);
  hal::fan_pwm::on_tick();
  g_phase = static_cast<uint8_t>(phase + 1) & (hal::adc::kSamplesPerWindow - 1);
  g_millis = g_millis + 1;
}

}  // namespace

ISR(TIMER0_COMPA_vect) { on_tick(); }

namespace hal {
namespace tick {

void init() {
  TCCR0A = (1 << WGM01);               // CTC, TOP = OCR0A
  TCCR0B = (1 << CS01) | (1 << CS00);  // clk / 64 = 250 kHz
  // OCR0A after the clock select: simavr 1.6 applies the WGM bits only when TCCR0B is
  // written and warns about an OCR write in "mode 0" before that. The counter cannot reach
  // a compare in the few cycles between the two writes (one count = 64 cycles).
  OCR0A = 249;                         // 250 counts of 4 us
  TIMSK0 = (1 << OCIE0A);
}

uint32_t millis() {
  CriticalSection lock;  // 32-bit value written by the ISR
  return g_millis;
}

}  // namespace tick
}  // namespace hal
