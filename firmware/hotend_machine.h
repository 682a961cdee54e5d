// The firmware's gcode::Machine: what G-code commands do to this board -- the heater manager,
// the controllers (through the controller bank and its M-codes), the fan, faults and settings.
// All validation of command syntax and ranges happens in the G-code layer and in
// ControllerCommands; this class refuses only what depends on machine state.
#pragma once
#include <stdint.h>

#include "firmware/control_loop.h"
#include "firmware/controller_autotune.h"
#include "firmware/controller_bank.h"
#include "firmware/controller_commands.h"
#include "firmware/gcode_machine.h"
#include "firmware/heater_manager.h"
#include "firmware/settings.h"
#include "firmware/settings_writer.h"

namespace firmware {

// Highest target M104/M109 accept: 275 degC (10 degC under MAXTEMP, see range_guard.h).
constexpr int32_t kMaxTargetQ8 = 275L * 256;

class HotendMachine final : public gcode::Machine {
 public:
  constexpr HotendMachine(HeaterManager& heater, ControlLoop& loop, ControllerBank& bank, AutotuneJob& tune,
                          gcode::Output& out)
      : heater_(heater), loop_(loop), bank_(bank), tune_(tune), commands_(bank), out_(out) {}

  // Start-up: settings from EEPROM, or the defaults with a message when it holds none.
  void load_settings_at_boot();

  gcode::HeaterStatus heater_status() override;
  int32_t max_target_q8() override { return kMaxTargetQ8; }
  const gcode::FlashText* set_target_q8(int32_t target_q8) override;
  gcode::PidGainsQ16 pid_gains() override;
  const gcode::FlashText* set_pid_gains(const gcode::PidGainsQ16& gains) override;
  void set_fan_duty(uint8_t duty) override;
  void emergency_stop() override;
  const gcode::FlashText* clear_fault() override;
  const gcode::FlashText* save_settings() override;
  const gcode::FlashText* load_settings() override;
  void reset_settings() override;
  const gcode::FlashText* firmware_version() override;
  const gcode::FlashText* machine_type() override;
  void hang_for_watchdog() override;
  bool handle_command(const gcode::Command& cmd, gcode::Output& out) override;
  void report_settings(gcode::Output& out) override { commands_.report(out); }
  void background(gcode::Output& out) override;
  void cancel_heating() override { tune_.stop(AutotuneJob::Stop::kUser); }
  bool command_pending() override { return writer_.writing(); }

 private:
  HandOver hand_over() const;
  // M501 / boot: the EEPROM block, all or nothing; the reason for refusing, or nullptr.
  const gcode::FlashText* load_stored();

  HeaterManager& heater_;
  ControlLoop& loop_;
  ControllerBank& bank_;  // holds the settings in force (what M500 saves)
  AutotuneJob& tune_;     // M303
  ControllerCommands commands_;
  gcode::Output& out_;
  SettingsWriter writer_;  // M500 in progress
};

}  // namespace firmware
