#include "firmware/hotend_machine.h"

#include "firmware/flash_text.h"
#include "hal/board.h"
#include "hal/fan_pwm.h"
#include "hal/uart.h"
#include "hal/watchdog.h"

namespace firmware {
namespace {
FIRMWARE_FLASH_JOIN(kMachineType, board::kName, " hotend");

// A block with a good CRC can still hold gains this build's PID cannot represent (written by
// another version): configure() must never see those, so such a block counts as invalid.
bool load_usable_settings(Settings& out) {
  Settings settings;
  if (!load_settings(settings) || !control::Pid::valid(settings.pid, kControlPeriodMs)) return false;
  out = settings;
  return true;
}

}  // namespace

void HotendMachine::load_settings_at_boot() {
  Settings settings = default_settings();
  if (load_usable_settings(settings)) {
    out_.write_flash(GCODE_TEXT("echo:Settings loaded from EEPROM\n"));
  } else {
    out_.write_flash(GCODE_TEXT("echo:EEPROM invalid (blank or corrupt), defaults loaded\n"));
  }
  apply(settings);
}

void HotendMachine::apply(const Settings& settings) {
  settings_ = settings;
  pid_.configure(settings.pid, kControlPeriodMs);
}

gcode::HeaterStatus HotendMachine::heater_status() {
  return gcode::HeaterStatus{loop_.temp_q8(), heater_.target_q8(), heater_.duty_q16(),
                             heater_.fault() != Fault::kNone};
}

const gcode::FlashText* HotendMachine::set_target_q8(int32_t target_q8) {
  return heater_.set_target_q8(target_q8);
}

gcode::PidGainsQ16 HotendMachine::pid_gains() {
  return gcode::PidGainsQ16{settings_.pid.kp_q16, settings_.pid.ki_q16, settings_.pid.kd_q16};
}

const gcode::FlashText* HotendMachine::set_pid_gains(const gcode::PidGainsQ16& gains) {
  const control::PidGains pid{gains.kp_q16, gains.ki_q16, gains.kd_q16};
  if (!control::Pid::valid(pid, kControlPeriodMs)) return GCODE_TEXT("M301 gains beyond what the fixed-point PID holds");
  Settings next = settings_;
  next.pid = pid;
  apply(next);
  return nullptr;
}

void HotendMachine::set_fan_duty(uint8_t duty) { hal::fan_pwm::set_duty(duty); }

// The G-code layer prints the Error line for M112 itself.
void HotendMachine::emergency_stop() { heater_.trip(Fault::kEmergencyStop); }

const gcode::FlashText* HotendMachine::clear_fault() {
  const Fault fault = heater_.fault();
  if (fault == Fault::kNone) return nullptr;
  // Refused while the thermistor still reads out of range, whatever fault was latched first.
  if (loop_.reading_bad()) {
    return loop_.reading_fault() == Fault::kMinTemp ? GCODE_TEXT("M999 refused: MINTEMP condition persists")
                                                    : GCODE_TEXT("M999 refused: MAXTEMP condition persists");
  }
  heater_.clear_fault();
  out_.write_flash(GCODE_TEXT("echo:Fault cleared, heater off until a new target\n"));
  return nullptr;
}

const gcode::FlashText* HotendMachine::save_settings() {
  firmware::save_settings(settings_);
  return nullptr;
}

const gcode::FlashText* HotendMachine::load_settings() {
  Settings settings;
  if (!load_usable_settings(settings)) return GCODE_TEXT("EEPROM invalid (blank or corrupt), settings unchanged");
  apply(settings);
  return nullptr;
}

void HotendMachine::reset_settings() { apply(default_settings()); }

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
