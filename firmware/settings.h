// Settings kept in EEPROM (M500 save, M501 load, M502 defaults, M503 report): the controller
// settings (firmware/controller_settings.h) and the state-feedback constants.
//
// Two slots, each a complete copy: [sequence][magic, layout version, size][block][CRC-16]. M500
// (firmware/settings_writer.h) writes the slot that does not hold the newest copy: first its
// sequence byte := 0xFF (the slot no longer counts), then the header, block and CRC (changed
// bytes only), and the new sequence byte last. A reset at any byte leaves the other slot, with
// the old settings, as the newest valid one; after the last byte the new slot wins. (A single
// copy with its CRC written last would only detect the tear: the old settings would be lost
// and the defaults come back.) The CRC also rejects worn cells, a blank (0xFF) EEPROM and
// blocks written by another layout.
#pragma once
#include <stdint.h>

#include "control/state_feedback_constants.h"
#include "firmware/controller_settings.h"

namespace firmware {

// What one slot holds besides its sequence, header and CRC.
struct SettingsBlock {
  Settings settings;
  uint8_t sf_loaded;                   // 1: `sf` holds constants M311 W1 accepted
  control::StateFeedbackConstants sf;  // ignored when sf_loaded is 0
};

namespace settings_layout {

constexpr uint8_t kSlotCount = 2;
constexpr uint16_t kSlotStride = 512;  // room to grow: both chips have 4 KB of EEPROM
constexpr uint8_t kNoSequence = 0xFF;  // erased / being written: the slot does not count
constexpr uint8_t kHeaderSize = 5;     // magic (2), layout version, block size (2)

// Byte offsets inside a slot, in the order the CRC covers them.
constexpr uint16_t kSequenceOffset = 0;
constexpr uint16_t kHeaderOffset = 1;
constexpr uint16_t kSettingsOffset = kHeaderOffset + kHeaderSize;
constexpr uint16_t kFlagOffset = kSettingsOffset + sizeof(Settings);
constexpr uint16_t kSfOffset = kFlagOffset + 1;
constexpr uint16_t kCrcOffset = kSfOffset + sizeof(control::StateFeedbackConstants);
constexpr uint16_t kSlotSize = kCrcOffset + 2;
static_assert(kSlotSize <= kSlotStride, "a settings slot outgrew its EEPROM stride");

constexpr uint16_t slot_address(uint8_t slot) { return static_cast<uint16_t>(slot * kSlotStride); }
// The header bytes this build writes and accepts.
uint8_t header_byte(uint8_t index);
// Sequence numbers run 0..254 and wrap; 0xFF is never one.
constexpr uint8_t next_sequence(uint8_t seq) { return seq >= 254 ? 0 : static_cast<uint8_t>(seq + 1); }

// Each slot's validity and sequence; `newest` is the slot to load (-1: none valid).
struct Scan {
  bool valid[kSlotCount];
  uint8_t sequence[kSlotCount];
  int8_t newest;
};
Scan scan();
// Whether `slot` holds a valid block (sequence set, this layout, CRC); copies it into `out`
// unless out is nullptr.
bool read_slot(uint8_t slot, SettingsBlock* out, uint8_t* sequence);

}  // namespace settings_layout

// False when neither slot holds a valid block (blank, corrupt, other layout); `out` is scratch
// then (the caller's temporary: nothing in force changes).
bool load_settings(SettingsBlock& out);

// CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF): detects any 1- or 2-bit error and any burst
// up to 16 bits in the block -- what a worn cell produces. `crc` continues a CRC over earlier
// bytes (start with 0xFFFF).
uint16_t crc16_ccitt(uint16_t crc, const void* data, uint16_t size);

}  // namespace firmware
