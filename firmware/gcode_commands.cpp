// The built-in commands. Each reads and range-checks every parameter first and only then calls
// the machine, so a refused line changes nothing. "ok" is added by Interpreter::execute().
#include "firmware/gcode_interpreter.h"

namespace gcode {
namespace {

constexpr int32_t kMaxGainQ16 = 32767l << 16;  // what a Q16 int32 holds (in whole units)

}  // namespace

Interpreter::Handler Interpreter::handler_for(const Command& cmd) const {
  if (cmd.letter == 'T') return &Interpreter::select_tool;
  if (cmd.letter == 'D') return cmd.code == 0 ? &Interpreter::hang : nullptr;
  if (cmd.letter != 'M') return nullptr;
  switch (cmd.code) {
    case 104: return &Interpreter::set_target;
    case 105: return &Interpreter::report_temperatures;
    case 106: return &Interpreter::fan_on;
    case 107: return &Interpreter::fan_off;
    case 108: return &Interpreter::nothing;  // acted on by urgent() when its bytes arrived
    case 109: return &Interpreter::set_target_and_wait;
    case 110: return &Interpreter::set_line_number;
    case 112: return &Interpreter::nothing;
    case 115: return &Interpreter::firmware_info;
    case 155: return &Interpreter::set_autoreport;
    case 301: return &Interpreter::pid;
    case 500: return &Interpreter::save_settings;
    case 501: return &Interpreter::load_settings;
    case 502: return &Interpreter::reset_settings;
    case 503: return &Interpreter::report_settings;
    case 999: return &Interpreter::clear_fault;
    default: return nullptr;
  }
}

// Target from S (or R for M109) in °C; only T0 exists. Prints the Error and returns false on bad input.
bool Interpreter::read_target(const Command& cmd, char p, int32_t* target_q8) {
  int32_t tool = 0;
  return cmd.integer('T', 0, 0, &tool, out_) &&
         cmd.fixed(p, 8, 0, machine_.max_target_q8(), target_q8, out_);
}

void Interpreter::set_target(const Command& cmd) {
  int32_t target_q8 = 0;
  if (!cmd.require('S', out_) || !read_target(cmd, 'S', &target_q8)) return;
  out_.refusal_line(machine_.set_target_q8(target_q8));
}

// M109 S waits only when heating (as in Marlin); M109 R waits for heating or cooling.
void Interpreter::set_target_and_wait(const Command& cmd) {
  const char p = cmd.has('S') ? 'S' : 'R';
  int32_t target_q8 = 0;
  if (!cmd.require(p, out_) || !read_target(cmd, p, &target_q8)) return;
  const FlashText* refusal = machine_.set_target_q8(target_q8);
  if (refusal != nullptr) return out_.error_line(refusal);
  wait_ = p == 'S' ? Wait::kHeating : Wait::kReach;
  last_report_ms_ = now_ms_;
}

void Interpreter::report_temperatures(const Command& cmd) {
  int32_t tool = 0;
  if (!cmd.integer('T', 0, 0, &tool, out_)) return;
  out_.print(GCODE_TEXT("ok "));  // this line is the "ok"; execute() must not add one
  write_temperatures();
  out_.end_line();
  ok_sent_ = true;
}

void Interpreter::set_autoreport(const Command& cmd) {
  int32_t interval_s = 0;
  if (!cmd.require('S', out_) || !cmd.integer('S', 0, 60, &interval_s, out_)) return;
  autoreport_s_ = static_cast<uint8_t>(interval_s);
  last_report_ms_ = now_ms_;
}

void Interpreter::pid(const Command& cmd) {
  PidGainsQ16 gains = machine_.pid_gains();
  if (!cmd.q16('P', 0, kMaxGainQ16, &gains.kp_q16, out_) ||
      !cmd.q16('I', 0, kMaxGainQ16, &gains.ki_q16, out_) ||
      !cmd.q16('D', 0, kMaxGainQ16, &gains.kd_q16, out_)) {
    return;
  }
  if (cmd.has('P') || cmd.has('I') || cmd.has('D')) {
    const FlashText* refusal = machine_.set_pid_gains(gains);
    if (refusal != nullptr) return out_.error_line(refusal);
  }
  write_pid_gains();
}

void Interpreter::write_pid_gains() {
  // Marlin's M301 report, which host plugins parse: "echo: p:22.20 i:1.08 d:114.00".
  const PidGainsQ16 gains = machine_.pid_gains();
  out_.print(GCODE_TEXT("echo: p:"));
  out_.write_q16(gains.kp_q16);
  out_.print(GCODE_TEXT(" i:"));
  out_.write_q16(gains.ki_q16);
  out_.print(GCODE_TEXT(" d:"));
  out_.write_q16(gains.kd_q16);
  out_.end_line();
}

void Interpreter::fan_on(const Command& cmd) {
  int32_t duty_q8 = 255l << 8;  // bare M106: full speed
  if (!cmd.fixed('S', 8, 0, 255l << 8, &duty_q8, out_)) return;
  machine_.set_fan_duty(static_cast<uint8_t>((duty_q8 + 128) >> 8));  // Cura sends S127.5
}

void Interpreter::fan_off(const Command&) { machine_.set_fan_duty(0); }

void Interpreter::set_line_number(const Command& cmd) {
  // "N41 M110" already set last_line_ = 41 in process_line(); "M110 N41" sets it here.
  cmd.fixed('N', 0, 0, kMaxLineNumber - 1, &last_line_, out_);
}

void Interpreter::nothing(const Command&) {}

void Interpreter::select_tool(const Command& cmd) {
  if (cmd.code == 0) return;  // slicers emit T0; there is one hotend
  cmd.begin_error(out_);
  out_.print(GCODE_TEXT(": only T0 exists\n"));
}

void Interpreter::hang(const Command&) { machine_.hang_for_watchdog(); }

void Interpreter::clear_fault(const Command&) { out_.refusal_line(machine_.clear_fault()); }

}  // namespace gcode
