// The hardware watchdog: a hung main loop resets the board, and the reset drives the heater
// low (.init3). Kicked only by the control loop, so a loop that stops controlling resets.
#pragma once
#include <stdint.h>

namespace hal {
namespace watchdog {

constexpr uint16_t kTimeoutMs = 500;

void enable();  // ~500 ms timeout (WDTO_500MS; the watchdog oscillator is +-10 % or worse)
void kick();

// Debug (D0): interrupts off, spin without kicking, until the watchdog resets the board.
[[noreturn]] void hang_until_reset();

}  // namespace watchdog
}  // namespace hal
