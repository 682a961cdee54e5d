// M115 firmware information and the settings commands M500-M503.
#include "firmware/gcode_interpreter.h"

namespace gcode {

void Interpreter::firmware_info(const Command&) {
  // Key:value pairs and "Cap:" lines as Marlin prints them; hosts enable features from these.
  out_.print(GCODE_TEXT("FIRMWARE_NAME:hotend-controller FIRMWARE_VERSION:"));
  out_.print(machine_.firmware_version());
  out_.print(GCODE_TEXT(" PROTOCOL_VERSION:1.0 MACHINE_TYPE:"));
  out_.print(machine_.machine_type());
  out_.print(GCODE_TEXT(
      " EXTRUDER_COUNT:1\n"
      "Cap:AUTOREPORT_TEMP:1\n"
      "Cap:EEPROM:1\n"
      // M112/M108 are honoured during M109 waits, but a line held behind a wait blocks input,
      // so we do not claim Marlin's byte-level emergency parser.
      "Cap:EMERGENCY_PARSER:1\n"
      "Cap:SERIAL_XON_XOFF:0\n"));
}

void Interpreter::save_settings(const Command&) {
  // The machine reports "Settings stored" when the write has ended (command_pending()).
  const FlashText* refusal = machine_.save_settings();
  if (refusal != nullptr) return out_.error_line(refusal);
}

void Interpreter::load_settings(const Command&) {
  const FlashText* refusal = machine_.load_settings();
  if (refusal != nullptr) return out_.error_line(refusal);
  out_.print(GCODE_TEXT("echo:Settings loaded\n"));
}

void Interpreter::reset_settings(const Command&) {
  machine_.reset_settings();
  out_.print(GCODE_TEXT("echo:Default settings loaded (M500 stores them)\n"));
}

void Interpreter::report_settings(const Command&) {
  // M503: the settings as the commands that would set them, in an order in which replaying
  // them is accepted line by line: the machine's lines (M307, M312, M311, M310) before M301.
  // M301's gains are checked with the fuzzy spread (M312 S) in force, so M312 must come first:
  // after M502 the default gains hold any spread (0..100 %), while gains stored with a small
  // spread may not hold the default 50 %.
  machine_.report_settings(out_);
  const PidGainsQ16 gains = machine_.pid_gains();
  out_.print(GCODE_TEXT("echo:; Hotend PID (Marlin units):\necho:  M301 P"));
  out_.write_q16(gains.kp_q16);
  out_.print(GCODE_TEXT(" I"));
  out_.write_q16(gains.ki_q16);
  out_.print(GCODE_TEXT(" D"));
  out_.write_q16(gains.kd_q16);
  out_.end_line();
}

}  // namespace gcode
