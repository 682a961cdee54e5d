#include "firmware/temperature_sensor.h"

#include <avr/pgmspace.h>

#include "control/thermistor.h"

namespace firmware {
namespace sensor {
namespace {

constexpr int kEntries = thermistor::kDefaultTableSize;

// Built by the compiler from the sensor model (constexpr), then placed in flash: a constant
// initialiser, so no start-up code writes it and it costs no RAM.
constexpr thermistor::Table<kEntries> kTableValue =
    thermistor::make_table<kEntries>(kHotend, board::kThermistorPullupOhm);
const thermistor::Table<kEntries> kTable PROGMEM = kTableValue;

// Flash reads as non-volatile asm (avr-libc's pgm_read_* are volatile): the table never
// changes, so the compiler may drop reads of fields the caller does not use -- the binary
// search only looks at adc_q6. `lpm` reaches the first 64 KB, where PROGMEM data is placed.
__attribute__((always_inline)) inline uint16_t flash_u16(const void* address) {
  uint16_t value;
  __asm__("lpm %A0, Z+\n\tlpm %B0, Z" : "=r"(value), "+z"(address));
  return value;
}
__attribute__((always_inline)) inline uint32_t flash_u32(const void* address) {
  uint32_t value;
  __asm__("lpm %A0, Z+\n\tlpm %B0, Z+\n\tlpm %C0, Z+\n\tlpm %D0, Z" : "=r"(value), "+z"(address));
  return value;
}

// One entry from flash, field by field and inlined: a memcpy_P through a stack copy cost
// ~200 cycles per entry, which alone broke the 2,000-cycle control-step budget (simavr).
__attribute__((always_inline)) inline thermistor::Entry load_entry(uint8_t index) {
  const thermistor::Entry* entry = &kTable.entry[index];
  return thermistor::Entry{flash_u16(&entry->adc_q6), static_cast<int32_t>(flash_u32(&entry->temp_q8)),
                           flash_u16(&entry->slope_q11)};
}

}  // namespace

int32_t adc_q6_to_temp_q8(uint16_t adc_q6) {
  return thermistor::adc_q6_to_temp_q8(load_entry, static_cast<uint8_t>(kEntries), adc_q6);
}

}  // namespace sensor
}  // namespace firmware
