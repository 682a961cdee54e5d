// Byte-addressed EEPROM access for the settings block (avr-libc eeprom_* routines; they wait
// for a running write, so calls block ~3.4 ms per changed byte written).
#pragma once
#include <stdint.h>

namespace hal {
namespace eeprom {

void read(uint16_t address, void* data, uint16_t size);

// Writes only the bytes that differ (saves wear and time).
void update(uint16_t address, const void* data, uint16_t size);

}  // namespace eeprom
}  // namespace hal
