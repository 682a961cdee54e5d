// Test rig for the issue-3 firmware layer: the real ControllerBank and ControllerCommands behind
// the real G-code Interpreter, with a gcode::Machine that does what firmware/hotend_machine.cpp
// does for the calls that reach the controllers (M301, M502, the extension hooks) and nothing
// for the hardware ones. Also a closed-loop helper on hotend40w.
#pragma once
#include <stdint.h>

#include <sstream>
#include <string>
#include <vector>

#include "control/fuzzy_surface_gen.h"
#include "firmware/controller_bank.h"
#include "firmware/controller_commands.h"
#include "firmware/gcode_interpreter.h"
#include "host_tests/gcode_fakes.h"
#include "host_tests/hotend40w_model.h"

namespace controller_test {

inline fuzzy::Cell load_cell(uint16_t index) {
  static constexpr auto kSurfaces = fuzzy::make_default_surfaces();
  return kSurfaces.cell[index];
}

class BankMachine final : public gcode::Machine {
 public:
  BankMachine() {
    bank.init(firmware::default_settings());
    commands.sync_staging();
  }
  gcode::HeaterStatus heater_status() override { return {now.measured_q8, 0, now.duty_q16, false}; }
  int32_t max_target_q8() override { return 275L * 256; }
  const gcode::FlashText* set_target_q8(int32_t) override { return nullptr; }
  gcode::PidGainsQ16 pid_gains() override {
    const control::PidGains& g = bank.settings().pid;
    return {g.kp_q16, g.ki_q16, g.kd_q16};
  }
  const gcode::FlashText* set_pid_gains(const gcode::PidGainsQ16& g) override {
    firmware::Settings next = bank.settings();
    next.pid = control::PidGains{g.kp_q16, g.ki_q16, g.kd_q16};
    return bank.apply(next, now);
  }
  void set_fan_duty(uint8_t) override {}
  void emergency_stop() override {}
  const gcode::FlashText* clear_fault() override { return nullptr; }
  const gcode::FlashText* save_settings() override { return nullptr; }
  const gcode::FlashText* load_settings() override { return nullptr; }
  void reset_settings() override {
    bank.replace_all(firmware::default_settings(), nullptr, now);
    commands.sync_staging();
  }
  const gcode::FlashText* firmware_version() override { return GCODE_TEXT("test"); }
  const gcode::FlashText* machine_type() override { return GCODE_TEXT("test"); }
  void hang_for_watchdog() override {}
  bool handle_command(const gcode::Command& cmd, gcode::Output& out) override { return commands.handle(cmd, out, now); }
  void report_settings(gcode::Output& out) override { commands.report(out); }

  firmware::ControllerBank bank{load_cell};
  firmware::ControllerCommands commands{bank};
  firmware::HandOver now{25L * 256, 0, false};
};

struct Rig {
  BankMachine machine;
  gcode_test::StringOutput out;
  gcode::Interpreter gcode{machine, out};
  gcode::EmergencyParser emergency;

  std::string send(const std::string& text) {
    gcode_test::feed_like_firmware(emergency, gcode, text);
    return out.take();
  }
};

// M503's re-sendable lines ("echo:  M..."), without the prefix.
inline std::vector<std::string> settings_lines(Rig& rig) {
  std::istringstream report(rig.send("M503\n"));
  std::vector<std::string> lines;
  std::string line;
  while (std::getline(report, line))
    if (line.rfind("echo:  ", 0) == 0) lines.push_back(line.substr(7));
  return lines;
}

// The bank in closed loop on hotend40w at `target_c`: step() advances one control period and
// returns the duty the bank asked for.
struct Loop {
  explicit Loop(firmware::ControllerBank& b) : bank(b) {}
  firmware::ControllerBank& bank;
  test_plant::Hotend40w plant;
  double target_c = 210.0;
  uint8_t fan = 0;
  uint16_t duty_q16 = 0;

  uint16_t step() {
    const int32_t measured_q8 = test_plant::to_q8(plant.sensor_c());
    duty_q16 = bank.step(control::StepInput{test_plant::to_q8(target_c), measured_q8, fan});
    plant.set_fan(fan / 255.0);
    plant.advance(duty_q16 / 65535.0);
    return duty_q16;
  }
  firmware::HandOver hand_over() const { return {test_plant::to_q8(plant.sensor_c()), duty_q16, true}; }
};

}  // namespace controller_test
