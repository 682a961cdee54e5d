#include "firmware/serial_output.h"

#include <avr/pgmspace.h>

#include "hal/uart.h"

namespace firmware {

void SerialOutput::write_char(char c) { hal::uart::write(static_cast<uint8_t>(c)); }

void SerialOutput::write_flash(const gcode::FlashText* text) {
  const char* p = reinterpret_cast<const char*>(text);
  for (char c = static_cast<char>(pgm_read_byte(p)); c != '\0'; c = static_cast<char>(pgm_read_byte(++p))) {
    write_char(c);
  }
}

}  // namespace firmware
