#include "firmware/hotend_machine.h"

#include "firmware/flash_text.h"
#include "hal/board.h"
#include "hal/fan_pwm.h"
#include "hal/uart.h"
#include "hal/watchdog.h"

namespace firmware {
namespace {
FIRMWARE_FLASH_JOIN(kMachineType, board::kName, " hotend");
}  // namespace

HandOver HotendMachine::hand_over() const {
  return HandOver{loop_.temp_q8(), heater_.duty_q16(), heater_.target_q8() != 0 && heater_.fault() == Fault::kNone};
}

// A block with a good CRC can still hold settings this build cannot use (written by another
// version): the bank checks everything before it applies anything, so such a block counts as
// invalid and changes nothing.
const gcode::FlashText* HotendMachine::load_stored() {
  SettingsBlock block;  // scratch (~210 bytes of stack, only here)
  if (!firmware::load_settings(block)) return GCODE_TEXT("EEPROM invalid (blank or corrupt), settings unchanged");
  // The same checks as the G-code commands (ControllerBank::apply), so a block can hold nothing
  // M301/M307/M310/M311/M312 would refuse.
  const gcode::FlashText* refusal =
      block.sf_loaded > 1 ? GCODE_TEXT("state-feedback flag invalid")
                          : bank_.replace_all(block.settings, block.sf_loaded == 1 ? &block.sf : nullptr, hand_over());
  if (refusal != nullptr) {
    out_.print(GCODE_TEXT("echo:EEPROM settings refused: "));
    out_.print(refusal);
    out_.end_line();
    return GCODE_TEXT("EEPROM settings unusable by this firmware, settings unchanged");
  }
  commands_.sync_staging();
  return nullptr;
}

void HotendMachine::load_settings_at_boot() {
  bank_.init(default_settings());
  if (load_stored() == nullptr) {
    out_.write_flash(GCODE_TEXT("echo:Settings loaded from EEPROM\n"));
  } else {
    out_.write_flash(GCODE_TEXT("echo:EEPROM invalid (blank, corrupt or refused), defaults loaded\n"));
  }
  loop_.sync_protection(bank_.settings());  // before the first control period
}

gcode::HeaterStatus HotendMachine::heater_status() {
  return gcode::HeaterStatus{loop_.temp_q8(), heater_.target_q8(), heater_.duty_q16(),
                             heater_.fault() != Fault::kNone};
}

// While M303 runs, what would change the heater's target or the controllers is refused
// (autotune_busy_text()).
bool HotendMachine::handle_command(const gcode::Command& cmd, gcode::Output& out) {
  if (cmd.letter == 'M' && cmd.code == 303) {
    const gcode::FlashText* refusal = heater_.fault() != Fault::kNone
                                          ? GCODE_TEXT("PID Autotune failed! Heater fault latched, send M999 to clear")
                                          : (tune_.busy() ? autotune_busy_text() : nullptr);
    if (tune_.begin(cmd, out, refusal, hal::fan_pwm::duty(), loop_.hold_gain_q8())) heater_.set_target_q8(tune_.target_q8());
    return true;
  }
  // M307/M310/M311/M312/M570 with parameters change the settings; bare, they only report.
  const bool changes = cmd.letter == 'M' && ((cmd.code >= 307 && cmd.code <= 312) || cmd.code == 570) &&
                       cmd.params != nullptr && *cmd.params != '\0';
  if (changes && tune_.busy()) {
    out.error_line(autotune_busy_text());
    return true;
  }
  return commands_.handle(cmd, out, hand_over());
}

void HotendMachine::background(gcode::Output& out) {
  if (writer_.writing()) {
    const SettingsWriter::Status status = writer_.step();
    if (status == SettingsWriter::Status::kFailed) out.error_line(GCODE_TEXT("EEPROM write failed (read back invalid)"));
    if (status == SettingsWriter::Status::kDone) {
      out.print(GCODE_TEXT("echo:Settings stored ("));
      out.write_uint(writer_.bytes_written());
      out.print(GCODE_TEXT(" bytes written)\n"));
    }
  }
  loop_.sync_protection(bank_.settings());  // M307, M303 U1, M501/M502, M570 reach the protection here
  if (!tune_.busy()) return;
  // Heater off before the result's lines go out: a control step may run while they wait for
  // the TX ring, and with the target still set it would heat under the next controller. The
  // controllers take over only from the next target (HandOver: not heating).
  if (tune_.ended()) heater_.set_target_q8(0);
  if (!tune_.report(out, HandOver{loop_.temp_q8(), 0, false})) return;  // true only once ended
  loop_.set_fan_duty(tune_.fan_to_restore());
  bank_.prepare_feedforward(0);
}

const gcode::FlashText* HotendMachine::set_target_q8(int32_t target_q8) {
  if (tune_.busy()) {
    if (target_q8 != 0) return autotune_busy_text();
    tune_.stop(AutotuneJob::Stop::kUser);  // M104 S0: the report ends the job, heater off now
  }
  const gcode::FlashText* refusal = heater_.set_target_q8(target_q8);
  if (refusal == nullptr) bank_.prepare_feedforward(target_q8);
  return refusal;
}

gcode::PidGainsQ16 HotendMachine::pid_gains() {
  const control::PidGains& pid = bank_.settings().pid;
  return gcode::PidGainsQ16{pid.kp_q16, pid.ki_q16, pid.kd_q16};
}

const gcode::FlashText* HotendMachine::set_pid_gains(const gcode::PidGainsQ16& gains) {
  if (tune_.busy()) return autotune_busy_text();
  Settings next = bank_.settings();
  next.pid = control::PidGains{gains.kp_q16, gains.ki_q16, gains.kd_q16};
  return bank_.apply(next, hand_over());
}

void HotendMachine::set_fan_duty(uint8_t duty) {
  if (tune_.busy()) return tune_.set_fan_to_restore(duty);  // the tune drives the fan until it ends
  loop_.set_fan_duty(duty);  // the controllers follow its airflow from the next period
}

// The G-code layer prints the Error line for M112 itself.
void HotendMachine::emergency_stop() {
  heater_.trip(Fault::kEmergencyStop);
  tune_.stop(AutotuneJob::Stop::kUser);
}

const gcode::FlashText* HotendMachine::clear_fault() {
  const Fault fault = heater_.fault();
  if (fault == Fault::kNone) return nullptr;
  // Refused while the thermistor still reads out of range, whatever fault was latched first.
  if (loop_.reading_bad()) {
    return loop_.reading_fault() == Fault::kMinTemp ? GCODE_TEXT("M999 refused: MINTEMP condition persists")
                                                    : GCODE_TEXT("M999 refused: MAXTEMP condition persists");
  }
  heater_.clear_fault();
  loop_.restart_protection();
  out_.write_flash(GCODE_TEXT("echo:Fault cleared, heater off until a new target\n"));
  return nullptr;
}

// Starts the write; background() streams it and the G-code layer holds the "ok" until it has
// ended. The bank's objects are written as they are: M303 could change them mid-way.
const gcode::FlashText* HotendMachine::save_settings() {
  if (tune_.busy()) return autotune_busy_text();
  writer_.begin(bank_.settings(), bank_.state_feedback_loaded(), bank_.state_feedback_constants());
  return nullptr;
}

const gcode::FlashText* HotendMachine::load_settings() { return load_stored(); }

// The defaults hold no state-feedback constants: S1 and its upload are gone afterwards.
void HotendMachine::reset_settings() {
  bank_.replace_all(default_settings(), nullptr, hand_over());  // defaults are always accepted
  commands_.sync_staging();
}

const gcode::FlashText* HotendMachine::firmware_version() { return GCODE_TEXT(HOTEND_VERSION); }

const gcode::FlashText* HotendMachine::machine_type() { return kMachineType.flash(); }

// The heater pin is deliberately left as it is, as in a real hang: the test of this path is
// that the watchdog reset (.init3) switches it off, within the ~0.5 s timeout.
void HotendMachine::hang_for_watchdog() {
  out_.write_flash(GCODE_TEXT("echo:D0: hanging with interrupts off until the watchdog resets\n"));
  hal::uart::flush();
  hal::watchdog::hang_until_reset();
}

}  // namespace firmware
