#include "firmware/settings.h"

#include <string.h>

#include "hal/eeprom.h"

namespace firmware {
namespace {

constexpr uint16_t kMagic = 0x4854;  // "HT" (hotend)
constexpr uint8_t kLayoutVersion = 1;  // bump when Settings changes: old blocks then read invalid
constexpr uint16_t kEepromAddress = 0;

struct Stored {
  uint16_t magic;
  uint8_t version;
  uint8_t size;  // sizeof(Stored): catches a layout change that forgot the version bump
  Settings settings;
  uint16_t crc;  // over every byte above
};

constexpr uint16_t kCrcBytes = sizeof(Stored) - sizeof(uint16_t);
static_assert(sizeof(Stored) < 256, "size field is one byte");

// Q16 from a decimal value given in thousandths (keeps the defaults readable and exact).
constexpr int32_t q16_from_milli(int32_t milli) {
  return static_cast<int32_t>((static_cast<int64_t>(milli) * 65536 + 500) / 1000);
}

}  // namespace

uint16_t crc16_ccitt(const uint8_t* data, uint16_t size) {
  uint16_t crc = 0xFFFF;
  for (uint16_t i = 0; i < size; ++i) {
    crc ^= static_cast<uint16_t>(data[i]) << 8;
    for (uint8_t bit = 0; bit < 8; ++bit) {
      crc = (crc & 0x8000) ? static_cast<uint16_t>((crc << 1) ^ 0x1021) : static_cast<uint16_t>(crc << 1);
    }
  }
  return crc;
}

// Defaults for the hotend40w plant (E3D-V6 class: block 16.7 J/K, 40 W, loss 0.068 W/K,
// sensor lag 0.22 /s), Marlin units: Kp per degC on the 0..255 scale, Ki per degC.s, Kd s.
// Chosen by a grid search (Kp 14..40, Ki 0.5..2, Kd 40..140) on a double-precision model of
// that plant under control/pid.h's structure (128 ms period, conditional integration,
// derivative on measurement, 1 s filter): the smallest worst-case overshoot over heater power
// 32..48 W, heat capacity 13..21 J/K, sensor lag 0.15..0.3 /s and targets 180..250 degC,
// among gains whose nominal 25 -> 210 degC settling into +-1 degC is <= 104 s (full power
// alone needs ~99 s). Result: nominal overshoot 0, worst 0.5 degC; part-fan step dip 1.4 degC.
Settings default_settings() {
  Settings s;
  s.pid.kp_q16 = q16_from_milli(34000);
  s.pid.ki_q16 = q16_from_milli(1000);
  s.pid.kd_q16 = q16_from_milli(100000);
  return s;
}

bool load_settings(Settings& out) {
  Stored stored;
  hal::eeprom::read(kEepromAddress, &stored, sizeof stored);
  if (stored.magic != kMagic || stored.version != kLayoutVersion || stored.size != sizeof(Stored)) return false;
  if (stored.crc != crc16_ccitt(reinterpret_cast<const uint8_t*>(&stored), kCrcBytes)) return false;
  out = stored.settings;
  return true;
}

void save_settings(const Settings& settings) {
  Stored stored;
  memset(&stored, 0, sizeof stored);  // padding bytes (none on AVR) must not vary
  stored.magic = kMagic;
  stored.version = kLayoutVersion;
  stored.size = sizeof(Stored);
  stored.settings = settings;
  stored.crc = crc16_ccitt(reinterpret_cast<const uint8_t*>(&stored), kCrcBytes);
  hal::eeprom::update(kEepromAddress, &stored, sizeof stored);
}

}  // namespace firmware
