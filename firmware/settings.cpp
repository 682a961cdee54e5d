#include "firmware/settings.h"

#include "hal/eeprom.h"

namespace firmware {
namespace {

constexpr uint16_t kMagic = 0x4854;  // "HT" (hotend)
// Bump when SettingsBlock changes: old blocks then read invalid. 2: issue 3 (model, controller
// choice, fuzzy configuration, state-feedback constants). 3: issue 8 (model_tuned, M570).
constexpr uint8_t kLayoutVersion = 3;
constexpr uint16_t kEepromAddress = 0;

struct Header {
  uint16_t magic;
  uint8_t version;
  uint8_t size;  // sizeof(SettingsBlock): catches a layout change that forgot the version bump
};
static_assert(sizeof(SettingsBlock) < 256, "size field is one byte");

constexpr uint16_t kBlockAddress = kEepromAddress + sizeof(Header);
constexpr uint16_t kCrcAddress = kBlockAddress + sizeof(SettingsBlock);
// The block's parts in EEPROM order (AVR structs have no padding, so offsets are the sums).
constexpr uint16_t kSettingsAddress = kBlockAddress;
constexpr uint16_t kFlagAddress = kSettingsAddress + sizeof(Settings);
constexpr uint16_t kSfAddress = kFlagAddress + 1;
static_assert(kSfAddress + sizeof(control::StateFeedbackConstants) == kCrcAddress, "SettingsBlock has padding");

}  // namespace

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
  Header header;
  uint16_t crc;
  hal::eeprom::read(kEepromAddress, &header, sizeof header);
  if (header.magic != kMagic || header.version != kLayoutVersion || header.size != sizeof(SettingsBlock)) return false;
  hal::eeprom::read(kBlockAddress, &out, sizeof out);
  hal::eeprom::read(kCrcAddress, &crc, sizeof crc);
  return crc == crc16_ccitt(crc16_ccitt(0xFFFF, &header, sizeof header), &out, sizeof out);
}

void save_settings(const Settings& settings, bool sf_loaded, const control::StateFeedbackConstants& sf) {
  const Header header{kMagic, kLayoutVersion, sizeof(SettingsBlock)};
  const uint8_t flag = sf_loaded ? 1 : 0;
  uint16_t crc = crc16_ccitt(0xFFFF, &header, sizeof header);
  crc = crc16_ccitt(crc, &settings, sizeof settings);
  crc = crc16_ccitt(crc, &flag, 1);
  crc = crc16_ccitt(crc, &sf, sizeof sf);
  hal::eeprom::update(kEepromAddress, &header, sizeof header);
  hal::eeprom::update(kSettingsAddress, &settings, sizeof settings);
  hal::eeprom::update(kFlagAddress, &flag, 1);
  hal::eeprom::update(kSfAddress, &sf, sizeof sf);
  hal::eeprom::update(kCrcAddress, &crc, sizeof crc);
}

}  // namespace firmware
