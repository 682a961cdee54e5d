#include "firmware/settings.h"

#include "hal/eeprom.h"

namespace firmware {
namespace settings_layout {
namespace {

constexpr uint16_t kMagic = 0x4854;  // "HT" (hotend)
// Bump when SettingsBlock changes meaning: old blocks then read invalid. 2: issue 3 (model,
// controller choice, fuzzy configuration, state-feedback constants); 3: issue 8 (two slots;
// model_tuned and M570 in Settings).
constexpr uint8_t kLayoutVersion = 3;
constexpr uint16_t kBlockSize = kCrcOffset - kSettingsOffset;  // catches a forgotten version bump

// Reads `size` bytes at `address` into `out` (if any), folding them into *crc.
void read_into(uint16_t address, void* out, uint16_t size, uint16_t* crc) {
  uint8_t* bytes = static_cast<uint8_t*>(out);
  for (uint16_t i = 0; i < size; ++i) {
    const uint8_t b = hal::eeprom::read_byte(static_cast<uint16_t>(address + i));
    *crc = crc16_ccitt(*crc, &b, 1);
    if (bytes != nullptr) bytes[i] = b;
  }
}

}  // namespace

uint8_t header_byte(uint8_t index) {
  switch (index) {
    case 0: return static_cast<uint8_t>(kMagic & 0xFF);
    case 1: return static_cast<uint8_t>(kMagic >> 8);
    case 2: return kLayoutVersion;
    case 3: return static_cast<uint8_t>(kBlockSize & 0xFF);
    default: return static_cast<uint8_t>(kBlockSize >> 8);
  }
}

bool read_slot(uint8_t slot, SettingsBlock* out, uint8_t* sequence) {
  const uint16_t base = slot_address(slot);
  uint16_t crc = 0xFFFF;
  uint8_t seq;
  read_into(base + kSequenceOffset, &seq, 1, &crc);
  *sequence = seq;
  if (seq == kNoSequence) return false;
  for (uint8_t i = 0; i < kHeaderSize; ++i) {
    uint8_t b;
    read_into(static_cast<uint16_t>(base + kHeaderOffset + i), &b, 1, &crc);
    if (b != header_byte(i)) return false;
  }
  read_into(base + kSettingsOffset, out != nullptr ? &out->settings : nullptr, sizeof(Settings), &crc);
  read_into(base + kFlagOffset, out != nullptr ? &out->sf_loaded : nullptr, 1, &crc);
  read_into(base + kSfOffset, out != nullptr ? &out->sf : nullptr, sizeof(control::StateFeedbackConstants), &crc);
  uint16_t stored = 0;
  uint16_t unused = 0;
  read_into(base + kCrcOffset, &stored, sizeof stored, &unused);
  return stored == crc;
}

Scan scan() {
  Scan s{};
  s.newest = -1;
  for (uint8_t slot = 0; slot < kSlotCount; ++slot) {
    s.valid[slot] = read_slot(slot, nullptr, &s.sequence[slot]);
    if (!s.valid[slot]) continue;
    // The other slot is newer only if its sequence follows this one's (a writer always writes
    // newest + 1 into the older slot).
    if (s.newest < 0 || s.sequence[slot] == next_sequence(s.sequence[s.newest])) s.newest = static_cast<int8_t>(slot);
  }
  return s;
}

}  // namespace settings_layout

uint16_t crc16_ccitt(uint16_t crc, const void* data, uint16_t size) {
  const uint8_t* bytes = static_cast<const uint8_t*>(data);
  for (uint16_t i = 0; i < size; ++i) {
    crc ^= static_cast<uint16_t>(bytes[i]) << 8;
    for (uint8_t bit = 0; bit < 8; ++bit) {
      crc = (crc & 0x8000) ? static_cast<uint16_t>((crc << 1) ^ 0x1021) : static_cast<uint16_t>(crc << 1);
    }
  }
  return crc;
}

bool load_settings(SettingsBlock& out) {
  const settings_layout::Scan s = settings_layout::scan();
  if (s.newest < 0) return false;
  uint8_t sequence;
  return settings_layout::read_slot(static_cast<uint8_t>(s.newest), &out, &sequence);
}

}  // namespace firmware
