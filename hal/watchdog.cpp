#include "hal/watchdog.h"

#include <avr/interrupt.h>
#include <avr/wdt.h>

namespace hal {
namespace watchdog {

// wdt_enable runs the timed WDCE sequence with interrupts off (avr-libc).
void enable() { wdt_enable(WDTO_500MS); }

void kick() { wdt_reset(); }

void hang_until_reset() {
  cli();
  for (;;) {
    // No sleep here: sleeping with interrupts off would stop simavr, and on silicon the
    // watchdog would still fire; a plain spin is the honest "hung firmware" case.
    __asm__ volatile("");
  }
}

}  // namespace watchdog
}  // namespace hal
