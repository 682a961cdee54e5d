#include "firmware/banner.h"

#include "firmware/flash_text.h"
#include "hal/board.h"
#include "hal/startup.h"

namespace firmware {
namespace {

FIRMWARE_FLASH_JOIN(kVersionLine, "echo:Hotend controller " HOTEND_VERSION " on ", board::kName);

const gcode::FlashText* reset_cause_text(hal::startup::ResetCause cause) {
  using hal::startup::ResetCause;
  switch (cause) {
    case ResetCause::kPowerOn: return GCODE_TEXT("echo:Power-on reset\n");
    case ResetCause::kExternal: return GCODE_TEXT("echo:External reset\n");
    case ResetCause::kBrownOut: return GCODE_TEXT("echo:Brown-out reset\n");
    case ResetCause::kWatchdog: return GCODE_TEXT("echo:Watchdog reset\n");
    case ResetCause::kJtag: return GCODE_TEXT("echo:JTAG reset\n");
    case ResetCause::kUnknown: break;
  }
  // No MCUSR flag: a bootloader cleared them, or the program jumped to address 0.
  return GCODE_TEXT("echo:Reset cause unknown\n");
}

}  // namespace

void print_banner(gcode::Output& out) {
  out.write_flash(GCODE_TEXT("start\n"));
  out.write_flash(kVersionLine.flash());
  out.end_line();
  out.write_flash(reset_cause_text(hal::startup::reset_cause()));
}

}  // namespace firmware
