// Settings kept in EEPROM (M500 save, M501 load, M502 defaults, M503 report). The EEPROM
// block carries a magic number, a layout version and a CRC, so a blank (0xFF) or corrupt
// EEPROM, or one written by another layout, is recognised and the defaults are used instead.
#pragma once
#include <stdint.h>

#include "control/pid.h"

namespace firmware {

struct Settings {
  control::PidGains pid;  // Marlin units, Q16 (see defaults in settings.cpp for how chosen)
};

Settings default_settings();

// False when the EEPROM holds no valid block (blank, corrupt, other layout); `out` untouched.
bool load_settings(Settings& out);
void save_settings(const Settings& settings);

// CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF): detects any 1- or 2-bit error and any burst
// up to 16 bits in the block -- what a torn write or worn cell produces.
uint16_t crc16_ccitt(const uint8_t* data, uint16_t size);

}  // namespace firmware
