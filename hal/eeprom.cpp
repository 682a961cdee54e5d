#include "hal/eeprom.h"

#include <avr/eeprom.h>
#include <avr/io.h>

#include "hal/critical_section.h"

namespace hal {
namespace eeprom {

bool busy() { return (EECR & (1 << EEPE)) != 0; }

void read(uint16_t address, void* data, uint16_t size) {
  eeprom_read_block(data, reinterpret_cast<const void*>(address), size);
}

uint8_t read_byte(uint16_t address) { return eeprom_read_byte(reinterpret_cast<const uint8_t*>(address)); }

void start_write(uint16_t address, uint8_t value) {
  EEAR = address;
  EEDR = value;
  // EEPE must follow EEMPE within 4 cycles (datasheet, "EEPROM Control Register"): two SBIs
  // with interrupts off. EEPM1:0 stay 00 from reset: erase and write in one 3.4 ms operation.
  CriticalSection cs;
  __asm__ volatile(
      "sbi %[eecr], %[eempe]\n\t"
      "sbi %[eecr], %[eepe]"
      :
      : [eecr] "I"(_SFR_IO_ADDR(EECR)), [eempe] "I"(EEMPE), [eepe] "I"(EEPE)
      : "memory");
}

}  // namespace eeprom
}  // namespace hal
