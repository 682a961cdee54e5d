// The UART's byte observer: the emergency parser (gcode_emergency_parser.h) run inside the RX
// interrupt. M112 switches the heater pin off right there; M112 and M108 each leave a flag,
// which the main loop takes to latch the fault or end the wait and print the replies.
#pragma once
#include <stdint.h>

#include "firmware/gcode_emergency_parser.h"

namespace firmware {
namespace emergency_input {

void on_rx_byte(uint8_t byte, bool overrun);  // hal::uart::RxObserver (interrupt context)

bool pending();                // a flag is waiting for the main loop
bool stop_pending();           // an M112 is waiting (its interrupt already switched the heater off)
bool take(gcode::Urgent kind);  // main loop: true once per recognised command of that kind

}  // namespace emergency_input
}  // namespace firmware
