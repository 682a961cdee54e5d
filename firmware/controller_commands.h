// The issue-3 M-codes on the controller bank (contract: docs/controllers.md):
//   M307 A C D F   hotend model (feedforward)      M310 S F   controller choice, feedforward on/off
//   M311 I A..H    state-feedback constants upload M311 W1    commit the upload
//   M312 S E C     fuzzy-PID configuration
// Each validates every parameter before anything changes; bare forms report. Reached through
// gcode::Machine::handle_command / report_settings. Hardware-free (host-tested with the G-code
// layer's fakes).
#pragma once
#include <stdint.h>

#include "control/state_feedback_constants.h"
#include "firmware/controller_bank.h"
#include "firmware/gcode_command.h"
#include "firmware/gcode_output.h"

namespace firmware {

// "M307 A<rise> C<time constant> D<dead time> F<fan loss>\n" (M503 and M303's report).
void write_m307(gcode::Output& out, const control::HotendModel& model);

class ControllerCommands {
 public:
  explicit constexpr ControllerCommands(ControllerBank& bank) : bank_(bank) {}

  // True if `cmd` is one of the commands above (its replies printed, not "ok"); false otherwise.
  bool handle(const gcode::Command& cmd, gcode::Output& out, const HandOver& now);
  // The M503 lines: M307, M312, the M311 upload (if loaded), M310 last (S1 needs the upload).
  void report(gcode::Output& out);
  // The staging copy M311 writes into becomes the loaded constants (all zero if none): after
  // start-up, M501 and M502, so that one M311 field + W1 edits the constants in force.
  void sync_staging();

 private:
  void model(const gcode::Command& cmd, gcode::Output& out, const HandOver& now);     // M307
  void select(const gcode::Command& cmd, gcode::Output& out, const HandOver& now);    // M310
  void upload(const gcode::Command& cmd, gcode::Output& out, const HandOver& now);    // M311
  void fuzzy(const gcode::Command& cmd, gcode::Output& out, const HandOver& now);     // M312
  void write_model(gcode::Output& out) const;
  void protection(const gcode::Command& cmd, gcode::Output& out, const HandOver& now);  // M570
  void write_protection(gcode::Output& out) const;
  void write_selection(gcode::Output& out) const;
  void write_fuzzy(gcode::Output& out) const;
  void write_upload(gcode::Output& out, const gcode::FlashText* prefix) const;

  // M311's fields go to bank_.sf_staging() (storage shared with M303: refused while it runs).
  ControllerBank& bank_;
};

}  // namespace firmware
