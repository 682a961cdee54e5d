// Settings kept in EEPROM (M500 save, M501 load, M502 defaults, M503 report): the controller
// settings (firmware/controller_settings.h) and the state-feedback constants. The EEPROM
// block carries a magic number, a layout version and a CRC, so a blank (0xFF) or corrupt
// EEPROM, or one written by another layout, is recognised and the defaults are used instead.
#pragma once
#include <stdint.h>

#include "control/state_feedback_constants.h"
#include "firmware/controller_settings.h"

namespace firmware {

// What one EEPROM block holds besides its header and CRC.
struct SettingsBlock {
  Settings settings;
  uint8_t sf_loaded;                   // 1: `sf` holds constants M311 W1 accepted
  control::StateFeedbackConstants sf;  // ignored when sf_loaded is 0
};

// False when the EEPROM holds no valid block (blank, corrupt, other layout); `out` is scratch
// then (the caller's temporary: nothing in force changes).
bool load_settings(SettingsBlock& out);
// Streams the block (no RAM copy of the constants): only changed bytes are written.
void save_settings(const Settings& settings, bool sf_loaded, const control::StateFeedbackConstants& sf);

// CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF): detects any 1- or 2-bit error and any burst
// up to 16 bits in the block -- what a torn write or worn cell produces. `crc` continues a
// CRC over earlier bytes (start with 0xFFFF).
uint16_t crc16_ccitt(uint16_t crc, const void* data, uint16_t size);

}  // namespace firmware
