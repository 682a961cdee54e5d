// Idle sleep between interrupts: the CPU stops, timers, ADC and UART keep running, and any
// interrupt (the 1 kHz tick at the latest) wakes it.
#pragma once
#include <avr/interrupt.h>
#include <avr/sleep.h>

namespace hal {
namespace sleep {

inline void init() { set_sleep_mode(SLEEP_MODE_IDLE); }

// Sleeps unless has_work() says there is something to do. The check runs with interrupts
// off and `sei; sleep` is atomic (the instruction after SEI runs before any interrupt), so an
// interrupt that makes work between the check and the sleep still wakes the CPU at once.
template <class HasWork>
inline void idle_unless(HasWork has_work) {
  cli();
  if (!has_work()) {
    sleep_enable();
    sei();
    sleep_cpu();
    sleep_disable();
  }
  sei();
}

}  // namespace sleep
}  // namespace hal
