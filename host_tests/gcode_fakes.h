// Test doubles for the G-code layer: a Machine that records every call and an Output that
// collects replies in a string, plus helpers to send text and numbered/checksummed lines.
#pragma once
#include <stdint.h>

#include <string>
#include <vector>

#include "firmware/gcode_emergency_parser.h"
#include "firmware/gcode_interpreter.h"
#include "firmware/gcode_machine.h"
#include "firmware/gcode_output.h"

namespace gcode_test {

inline const char* text_of(const gcode::FlashText* text) {
  return reinterpret_cast<const char*>(text);  // host: FlashText is ordinary memory
}

class StringOutput final : public gcode::Output {
 public:
  void write_char(char c) override { text += c; }
  void write_flash(const gcode::FlashText* t) override { text += text_of(t); }
  std::string take() {
    std::string result;
    result.swap(text);
    return result;
  }
  std::string text;
};

class FakeMachine final : public gcode::Machine {
 public:
  gcode::HeaterStatus heater_status() override { return status; }
  int32_t max_target_q8() override { return max_target; }
  const gcode::FlashText* set_target_q8(int32_t target_q8) override {
    calls.push_back("set_target " + std::to_string(target_q8));
    if (refusal == nullptr) status.target_q8 = target_q8;
    return refusal;
  }
  gcode::PidGainsQ16 pid_gains() override { return gains; }
  const gcode::FlashText* set_pid_gains(const gcode::PidGainsQ16& g) override {
    calls.push_back("set_pid " + std::to_string(g.kp_q16) + " " + std::to_string(g.ki_q16) +
                    " " + std::to_string(g.kd_q16));
    if (refusal == nullptr) gains = g;
    return refusal;
  }
  void set_fan_duty(uint8_t duty) override { calls.push_back("fan " + std::to_string(duty)); }
  void emergency_stop() override {
    calls.push_back("emergency_stop");
    status.fault = true;
  }
  const gcode::FlashText* clear_fault() override { return record("clear_fault"); }
  const gcode::FlashText* save_settings() override { return record("save"); }
  const gcode::FlashText* load_settings() override { return record("load"); }
  void reset_settings() override { calls.push_back("reset"); }
  const gcode::FlashText* firmware_version() override { return GCODE_TEXT("1.2.3"); }
  const gcode::FlashText* machine_type() override { return GCODE_TEXT("Test board"); }
  void hang_for_watchdog() override { calls.push_back("hang"); }
  void cancel_heating() override { calls.push_back("cancel_heating"); }
  bool handle_command(const gcode::Command& cmd, gcode::Output& out) override {
    if (cmd.letter != 'M' || cmd.code != 900) return false;  // a stand-in extension command
    int32_t k = 0;
    if (!cmd.valid(out) || !cmd.require('K', out) || !cmd.integer('K', 0, 9, &k, out)) return true;
    calls.push_back("M900 " + std::to_string(k));
    return true;
  }
  void report_settings(gcode::Output& out) override { out.write("echo:  M900 K3\n"); }
  bool command_pending() override { return pending; }

  const gcode::FlashText* record(const char* name) {
    calls.push_back(name);
    return refusal;
  }

  gcode::HeaterStatus status{25 * 256, 0, 0, false};
  int32_t max_target = 275 * 256;
  gcode::PidGainsQ16 gains{22 * 65536 + 13107, 70779, 114 * 65536};  // 22.2, 1.08, 114
  const gcode::FlashText* refusal = nullptr;  // returned by every refusable call when set
  std::vector<std::string> calls;
  bool pending = false;  // command_pending(): the last command still works in the background
};

// line + "*<checksum>\n" (checksum = XOR of the bytes before '*', the host convention).
inline std::string checksummed(const std::string& line) {
  uint8_t checksum = 0;
  for (char c : line) checksum ^= static_cast<uint8_t>(c);
  return line + "*" + std::to_string(checksum) + "\n";
}

// "N<n> <command>*<checksum>" as hosts send it.
inline std::string numbered(int32_t n, const std::string& command) {
  return checksummed("N" + std::to_string(n) + " " + command);
}

// Feeds `text` the way the firmware does: each byte passes the emergency parser first (RX
// interrupt), and what it recognises reaches urgent() before the byte reaches the line layer.
inline void feed_like_firmware(gcode::EmergencyParser& emergency, gcode::Interpreter& gcode, const std::string& text) {
  for (char c : text) {
    const gcode::Urgent urgent = emergency.feed(static_cast<uint8_t>(c));
    if (urgent != gcode::Urgent::kNone) gcode.urgent(urgent);
    gcode.feed(c);
  }
}

// One interpreter wired to the fakes; send() feeds text and returns the replies it produced.
// Bytes go in as feed_like_firmware() sends them.
struct Rig {
  FakeMachine machine;
  StringOutput out;
  gcode::Interpreter gcode{machine, out};
  gcode::EmergencyParser emergency;

  std::string send(const std::string& text) {
    feed_like_firmware(emergency, gcode, text);
    return out.take();
  }
  // Bytes lost at this point of the stream (the UART's RxEvent::kLost).
  std::string lose() {
    gcode.input_lost();
    return out.take();
  }
  std::string poll(uint32_t now_ms) {
    gcode.poll(now_ms);
    return out.take();
  }
};

}  // namespace gcode_test
