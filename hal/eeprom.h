// Byte-addressed EEPROM access for the settings slots. A byte write takes 3.3-3.4 ms on the
// ATmega1284P/2560 (datasheet tWD_EEPROM 3.3 ms), during which the EEPROM can neither be read
// nor written: start_write() starts one and returns at once, busy() tells when it is done, so
// the settings writer (firmware/settings.h) never waits for the EEPROM inside the main loop.
#pragma once
#include <stdint.h>

namespace hal {
namespace eeprom {

// A write started by start_write() is still in progress (EEPE set).
bool busy();

// Waits for a write in progress (<= 3.4 ms): only at start-up and M501, never while a
// settings write is streaming (the writer reads only when !busy()).
void read(uint16_t address, void* data, uint16_t size);
uint8_t read_byte(uint16_t address);

// Precondition: !busy(). Starts an erase-and-write of one byte (~3.4 ms) and returns at once.
void start_write(uint16_t address, uint8_t value);

}  // namespace eeprom
}  // namespace hal
