// libFuzzer target for the EEPROM loader: what M501 and start-up do with whatever the EEPROM
// holds. Input byte 0 picks the case:
//   even: the rest is the raw EEPROM (header, sequence and CRC checks first);
//   odd:  the rest is a SettingsBlock's bytes, stored by the firmware's own writer with a valid
//         header, sequence and CRC (what another firmware build or a bit flip before the CRC
//         was computed leaves), so the range checks are what stands between it and the bank.
// Oracles: a block the loader and the bank accept passes every G-code range check, runs the
// control law free of UBSan reports, and M503's text of it replays on a fresh firmware with no
// Error; a refused block changes nothing.
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "firmware/settings.h"
#include "firmware/settings_writer.h"
#include "host_tests/controller_rig.h"
#include "host_tests/fake_eeprom.h"

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail) {
  std::fprintf(stderr, "oracle: %s\n%s\n", what, detail.c_str());
  std::abort();
}

// M503's re-sendable lines as one text, ready to send to another firmware.
std::string m503_lines(controller_test::Rig& rig) {
  std::string lines;
  for (const std::string& line : controller_test::settings_lines(rig)) lines += line + "\n";
  return lines;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  fake_eeprom::reset(0);
  if ((data[0] & 1) == 0) {
    std::copy(data + 1, data + std::min(size, fake_eeprom::state().cells.size() + 1),
              fake_eeprom::state().cells.begin());
  } else {
    firmware::SettingsBlock block;
    memset(&block, 0, sizeof block);
    memcpy(&block, data + 1, std::min(size - 1, sizeof block));
    firmware::SettingsWriter writer;
    writer.begin(block.settings, block.sf_loaded != 0, block.sf);
    while (writer.step() == firmware::SettingsWriter::Status::kWriting) {
    }
  }

  controller_test::Rig rig;
  const std::string before = m503_lines(rig);
  firmware::SettingsBlock loaded;
  if (!firmware::load_settings(loaded)) return 0;
  const gcode::FlashText* refusal =
      rig.machine.bank.replace_all(loaded.settings, loaded.sf_loaded == 1 ? &loaded.sf : nullptr, rig.machine.now);
  if (refusal != nullptr) {
    if (m503_lines(rig) != before) fail("a refused block changed the settings", before);
    return 0;
  }
  rig.machine.commands.sync_staging();
  if (!firmware::settings_fields_in_range(rig.machine.bank.settings())) fail("accepted settings out of range", "");
  // Enough periods for a state-feedback law with a long decimation to run several times.
  for (int32_t i = 0; i < 96; ++i) {
    const int32_t t = (i * 37) % 501;  // readings across 0..500 °C
    rig.machine.bank.step(control::StepInput{210L * 256, t * 256, static_cast<uint8_t>(i & 8 ? 255 : 0)});
  }
  const std::string lines = m503_lines(rig);
  controller_test::Rig fresh;
  const std::string replies = fresh.send(lines);
  if (replies.find("Error") != std::string::npos) fail("M503 of an accepted block does not replay", lines + replies);
  return 0;
}
