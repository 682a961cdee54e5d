#include "firmware/banner.h"

#include "firmware/flash_text.h"
#include "hal/board.h"
#include "hal/startup.h"

namespace firmware {
namespace {

FIRMWARE_FLASH_JOIN(kVersionLine, "echo:Hotend controller " HOTEND_VERSION " on ", board::kName);

// "Power-on" etc. for "echo:<name> reset"; nullptr when no MCUSR flag was set (a bootloader
// cleared them, or the program jumped to address 0).
const gcode::FlashText* reset_cause_name(hal::startup::ResetCause cause) {
  using hal::startup::ResetCause;
  switch (cause) {
    case ResetCause::kPowerOn: return GCODE_TEXT("Power-on");
    case ResetCause::kExternal: return GCODE_TEXT("External");
    case ResetCause::kBrownOut: return GCODE_TEXT("Brown-out");
    case ResetCause::kWatchdog: return GCODE_TEXT("Watchdog");
    case ResetCause::kJtag: return GCODE_TEXT("JTAG");
    case ResetCause::kUnknown: break;
  }
  return nullptr;
}

}  // namespace

void print_banner(gcode::Output& out) {
  out.write_flash(GCODE_TEXT("start\n"));
  out.write_flash(kVersionLine.flash());
  out.end_line();
  // "echo:Power-on reset", or "echo:Reset cause unknown": the shared parts stored once.
  const gcode::FlashText* name = reset_cause_name(hal::startup::reset_cause());
  out.write_flash(GCODE_TEXT("echo:"));
  if (name == nullptr) return out.write_flash(GCODE_TEXT("Reset cause unknown\n"));
  out.write_flash(name);
  out.write_flash(GCODE_TEXT(" reset\n"));
}

}  // namespace firmware
