// The G-code layer as the main loop sees it: bytes in, replies out, machine calls made.
//
// Main loop contract:
//   while (gcode.accepting() && uart_read(&byte)) gcode.feed(byte);
//   gcode.poll(now_ms);   // every pass; drives M109 waits and M155 auto-reports
// Every complete line is answered synchronously inside feed() (exactly one "ok" per non-empty
// line), except M109: its "ok" is deferred until poll() sees the target reached (temperature
// lines every second meanwhile). While waiting, M112 and M108 (cancel the wait) are still
// executed at once; any other line is held and accepting() turns false until the wait ends,
// so the rest of the input stays in the UART ring. M112 is executed before the line-number
// and checksum checks (a stop must never be lost to a protocol error; stopping twice is harmless).
#pragma once
#include <stdint.h>

#include "firmware/gcode_line.h"
#include "firmware/gcode_machine.h"
#include "firmware/gcode_output.h"

namespace gcode {

class Interpreter {
 public:
  Interpreter(Machine& machine, Output& out) : machine_(machine), out_(out) {}

  void feed(char byte);                  // one received byte
  bool accepting() const { return !held_; }  // false: a line is held behind an M109 wait
  void poll(uint32_t now_ms);            // time base for waits and auto-reports (ms, wraps)
  bool waiting() const { return wait_ != Wait::kNone; }

 private:
  enum class Wait : uint8_t { kNone, kHeating, kReach };  // M109 S (heat only) / M109 R (either way)

  void process_line(char* line);
  void execute(const Command& cmd, bool m112_done);
  bool dispatch(const Command& cmd);  // false: unknown command
  void finish_wait();
  void write_temperatures();
  void request_resend(const FlashText* reason);

  // Command handlers (gcode_commands.cpp); each validates everything before calling the machine.
  void set_target(const Command& cmd, bool wait);
  void set_autoreport(const Command& cmd);
  void pid(const Command& cmd);
  void fan(const Command& cmd);
  void set_line_number(const Command& cmd, bool numbered, int32_t line_number);
  void firmware_info();
  void report_settings();

  Machine& machine_;
  Output& out_;
  LineAssembler line_;
  int32_t last_line_ = 0;       // last accepted line number N (hosts start with M110 N0)
  uint32_t now_ms_ = 0;         // from the latest poll()
  uint32_t last_report_ms_ = 0; // last temperature line (wait or auto-report)
  uint8_t autoreport_s_ = 0;    // M155 interval, 0 = off
  Wait wait_ = Wait::kNone;
  bool held_ = false;           // line_ holds a complete line behind the wait
};

}  // namespace gcode
