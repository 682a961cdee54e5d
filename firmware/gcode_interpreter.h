// The G-code layer as the main loop sees it: bytes in, replies out, machine calls made.
//
// Main loop contract:
//   urgent(kind) for each M112/M108 the emergency parser saw in the byte stream (at once);
//   while (gcode.accepting() && uart_read(&byte)) gcode.feed(byte), or input_lost() where the
//   UART dropped bytes;
//   gcode.poll(now_ms);   // every pass; drives M109 waits and M155 auto-reports
// Every complete line is answered synchronously inside feed() (exactly one "ok" per non-empty
// line), except M109: its "ok" is deferred until poll() sees the target reached (temperature
// lines every second meanwhile). M112 and M108 act through urgent(), ahead of any queue; their
// lines, when they arrive, pass the wait and only get their "ok" (a line M108 must not cancel
// a wait that began after it; a line M112 still stops, silently if already stopped). Any other
// line is held during the wait and accepting() turns false until it ends, so the rest of the
// input stays in the UART ring. M112 is executed before the line-number and checksum checks (a
// stop must never be lost to a protocol error; stopping twice is harmless).
#pragma once
#include <stdint.h>

#include "firmware/gcode_emergency_parser.h"
#include "firmware/gcode_line.h"
#include "firmware/gcode_machine.h"
#include "firmware/gcode_output.h"

namespace gcode {

class Interpreter {
 public:
  // constexpr: a global instance is constant-initialized (no start-up constructor code).
  constexpr Interpreter(Machine& machine, Output& out) : machine_(machine), out_(out) {}

  void feed(char byte);                  // one received byte
  void input_lost();                     // the UART dropped bytes here (RxEvent::kLost)
  void urgent(Urgent kind);              // M112 / M108 taken from the byte stream
  bool accepting() const { return !held_; }  // false: a line is held behind an M109 wait
  void poll(uint32_t now_ms);            // time base for waits and auto-reports (ms, wraps)
  bool waiting() const { return wait_ != Wait::kNone; }

 private:
  // M109 S (heat only) / M109 R (either way) / a command the machine is still carrying out
  // (Machine::command_pending, e.g. M500 writing EEPROM).
  enum class Wait : uint8_t { kNone, kHeating, kReach, kMachine };

  using Handler = void (Interpreter::*)(const Command&);

  void process_line(char* line);
  void execute(const Command& cmd);
  Handler handler_for(const Command& cmd) const;  // nullptr: not a built-in command
  void emergency_stop();
  void echo_unknown(const char* typed);  // echo:Unknown command: "<typed>"
  void finish_wait();
  void write_temperatures();
  // Numbered: "Error:<reason>, Last Line: n" + "Resend: n+1" + ok; else "Error:<reason>, line
  // discarded" + ok. `bad_byte` >= 0 is appended to the reason as " 0xNN".
  void reject_line(bool numbered, const FlashText* reason, int16_t bad_byte = -1);
  void request_resend(const FlashText* reason) { reject_line(true, reason); }

  // Command handlers (gcode_commands.cpp); each validates everything before calling the machine.
  void set_target(const Command& cmd);           // M104
  void set_target_and_wait(const Command& cmd);  // M109
  bool read_target(const Command& cmd, char p, int32_t* target_q8);
  void report_temperatures(const Command& cmd);  // M105
  void set_autoreport(const Command& cmd);       // M155
  void pid(const Command& cmd);                  // M301
  void fan_on(const Command& cmd);               // M106
  void fan_off(const Command& cmd);              // M107
  void set_line_number(const Command& cmd);      // M110
  void firmware_info(const Command& cmd);        // M115
  void save_settings(const Command& cmd);        // M500
  void load_settings(const Command& cmd);        // M501
  void reset_settings(const Command& cmd);       // M502
  void report_settings(const Command& cmd);      // M503
  void clear_fault(const Command& cmd);          // M999
  void hang(const Command& cmd);                 // D0
  void select_tool(const Command& cmd);          // T<n>
  void nothing(const Command& cmd);              // M112, M108 (done before the line checks / urgent())
  void write_pid_gains();

  Machine& machine_;
  Output& out_;
  LineAssembler line_;
  int32_t last_line_ = 0;       // last accepted line number N (hosts start with M110 N0)
  uint32_t now_ms_ = 0;         // from the latest poll()
  uint32_t last_report_ms_ = 0; // last temperature line (wait or auto-report)
  uint8_t autoreport_s_ = 0;    // M155 interval, 0 = off
  Wait wait_ = Wait::kNone;
  bool held_ = false;           // line_ holds a complete line behind the wait
  bool ok_sent_ = false;        // the handler's reply already began with "ok" (M105)
};

}  // namespace gcode
