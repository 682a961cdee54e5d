// The interface the G-code layer drives: the firmware implements it with the heater manager,
// safety and settings; the host tests with a fake that records calls. All quantities are fixed
// point (brief: temp_q8 = °C × 256, duty_q16 = 65535 for 100 %, gains Q16 in Marlin units).
// Methods returning `const FlashText*` return nullptr when done, else the reason for refusing
// (printed as "Error:<reason>", and the machine must have changed nothing).
#pragma once
#include <stdint.h>

#include "firmware/gcode_command.h"
#include "firmware/gcode_output.h"
#include "firmware/gcode_text.h"

namespace gcode {

struct HeaterStatus {
  int32_t temp_q8;    // measured hotend temperature, °C × 256
  int32_t target_q8;  // current target, °C × 256 (0 = heater off)
  uint16_t duty_q16;  // heater power of the current period, 65535 = 100 %
  bool fault;         // a latched fault holds the heater off (ends an M109 wait)
};

struct PidGainsQ16 {  // Marlin units (M301): output 0-255 per °C, Ki per second, Kd seconds; Q16
  int32_t kp_q16;
  int32_t ki_q16;
  int32_t kd_q16;
};

class Machine {
 public:
  virtual HeaterStatus heater_status() = 0;
  virtual int32_t max_target_q8() = 0;  // targets above are refused by the G-code layer
  // M104/M109. Called only with 0 <= target_q8 <= max_target_q8(); may refuse (e.g. fault latched).
  virtual const FlashText* set_target_q8(int32_t target_q8) = 0;

  virtual PidGainsQ16 pid_gains() = 0;  // M301 report, M503
  // M301: every gain >= 0 (checked by the G-code layer); refuse what the controller can't hold.
  virtual const FlashText* set_pid_gains(const PidGainsQ16& gains) = 0;

  virtual void set_fan_duty(uint8_t duty) = 0;  // M106/M107, 0..255

  virtual void emergency_stop() = 0;             // M112: heater off, latched until M999
  virtual const FlashText* clear_fault() = 0;    // M999: refuse while the fault condition persists

  // M500 (EEPROM). It may only start the write: command_pending() then holds the "ok".
  virtual const FlashText* save_settings() = 0;
  virtual const FlashText* load_settings() = 0;  // M501 (refuse if the EEPROM copy is invalid)
  virtual void reset_settings() = 0;             // M502: built-in defaults, not saved

  virtual const FlashText* firmware_version() = 0;  // M115, e.g. "0.1.0"
  virtual const FlashText* machine_type() = 0;      // M115, e.g. "RAMPS 1.4 hotend"

  virtual void hang_for_watchdog() = 0;  // D0: interrupts off, spin until the watchdog resets

  // Extension points (issue 3: controller selection etc.).
  // Commands the G-code layer does not know: return true if handled (print reply/Error lines,
  // not "ok" — the layer prints it); false gives the "Unknown command" echo.
  virtual bool handle_command(const Command&, Output&) { return false; }
  // Extra "echo:" lines for M503 after the layer's own M301 line.
  virtual void report_settings(Output&) {}
  // Every main-loop pass (from Interpreter::poll): lines a background job (M303) has to print.
  virtual void background(Output&) {}
  // M108 (Marlin's break-and-continue): end a heating job such as M303, heater off.
  virtual void cancel_heating() {}
  // True while the last command's work goes on in background() (M500 streaming to EEPROM):
  // the layer defers that command's "ok" until it turns false and holds further lines, so no
  // command ever runs beside an unfinished one.
  virtual bool command_pending() { return false; }

 protected:
  ~Machine() = default;  // never deleted through this interface (no heap in the firmware)
};

}  // namespace gcode
