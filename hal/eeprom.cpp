#include "hal/eeprom.h"

#include <avr/eeprom.h>

namespace hal {
namespace eeprom {

void read(uint16_t address, void* data, uint16_t size) {
  eeprom_read_block(data, reinterpret_cast<const void*>(address), size);
}

void update(uint16_t address, const void* data, uint16_t size) {
  eeprom_update_block(data, reinterpret_cast<void*>(address), size);
}

}  // namespace eeprom
}  // namespace hal
