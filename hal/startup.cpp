// Code that runs before the C runtime initialises .data/.bss and before any constructor.
#include "hal/startup.h"

#include <avr/io.h>
#include <avr/wdt.h>

#include "hal/board.h"
#include "hal/gpio.h"

namespace {
// .noinit: the C runtime clears .bss after .init3, which would erase the captured flags.
uint8_t g_mcusr_at_reset __attribute__((section(".noinit")));

// Ordinary function (own stack frame) called from the naked .init3 hook below.
__attribute__((noinline)) void take_pins_and_reset_cause() {
  // Heater MOSFET gates low on every reset, whatever the cause (interrupts are still off).
  hal::gpio::drive_low(board::kHotendHeater);
  hal::gpio::drive_low(board::kBedHeater);
  g_mcusr_at_reset = MCUSR;
  // After a watchdog reset WDRF forces WDE on with the shortest timeout (datasheet "Watchdog
  // Timer"): clear WDRF first, then stop the watchdog, or the board resets again in ~16 ms.
  MCUSR = 0;
  wdt_disable();
}

}  // namespace

// Placed in .init3: runs right after the stack pointer and r1 are set up (.init2), before
// .data/.bss initialisation and constructors -- the earliest point C code may run. naked =
// no prologue/epilogue, so control falls through to .init4 afterwards; a naked function may
// not have a frame, hence the call.
extern "C" __attribute__((naked, used, section(".init3"))) void hal_startup_init3() {
  take_pins_and_reset_cause();
}

namespace hal {
namespace startup {

ResetCause reset_cause() {
  const uint8_t flags = g_mcusr_at_reset;
  // Checked in order of significance: several flags can be set together.
  if (flags & (1 << WDRF)) return ResetCause::kWatchdog;
  if (flags & (1 << BORF)) return ResetCause::kBrownOut;
  if (flags & (1 << EXTRF)) return ResetCause::kExternal;
  if (flags & (1 << PORF)) return ResetCause::kPowerOn;
  if (flags & (1 << JTRF)) return ResetCause::kJtag;
  return ResetCause::kUnknown;
}

}  // namespace startup
}  // namespace hal
