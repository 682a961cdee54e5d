// Line protocol (line numbers, checksums, resend requests), M109 waits and auto-reports.
// Command handlers are in gcode_commands.cpp.
#include "firmware/gcode_interpreter.h"

#include "firmware/gcode_number.h"

namespace gcode {
namespace {

constexpr uint16_t kWaitReportMs = 1000;    // temperature line period while M109 waits
constexpr int32_t kWaitWindowQ8 = 1 * 256;  // M109 is done within 1 °C of the target

// "N12 M105*34" split into line number, checksum verdict and command text.
struct LineFrame {
  bool numbered = false;
  bool number_ok = false;  // N followed by digits, at most kMaxLineNumber
  bool has_checksum = false;
  bool checksum_ok = false;
  int32_t number = 0;
  char* command = nullptr;
};

// Reads decimal digits at `s` (at least one) into *value; false if there is no digit or the
// number exceeds `max`. *end is the first character after the digits.
bool read_digits(char* s, int32_t max, int32_t* value, char** end) {
  if (!is_digit(*s)) return false;
  uint32_t result = 0;
  bool over = false;
  for (; is_digit(*s); ++s) {
    const uint32_t digit = static_cast<uint32_t>(*s - '0');
    // result * 10 + digit > max, decided without overflow or a 32-bit division.
    over = over || result > static_cast<uint32_t>(max) / 10u ||
           result * 10u > static_cast<uint32_t>(max) - digit;
    if (!over) result = result * 10u + digit;
  }
  *end = s;
  *value = static_cast<int32_t>(result);
  return !over;
}

// Start of the command text after an optional "N<digits>" (or "N-1").
char* after_line_number(char* line) {
  if (to_upper(*line) != 'N') return line;
  ++line;
  if (*line == '-') ++line;
  while (is_digit(*line)) ++line;
  return line;
}

// Frames the line in place: the '*' is overwritten with the end of the string.
LineFrame frame_line(char* line) {
  LineFrame frame;
  frame.command = after_line_number(line);
  if (frame.command != line) {
    frame.numbered = true;
    char* end = nullptr;
    if (line[1] == '-') {
      // printrun resets with "N-1 M110*15" (its next line is N0); only -1 is meaningful.
      int32_t one = 0;
      frame.number_ok = read_digits(line + 2, 1, &one, &end) && one == 1;
      frame.number = -1;
    } else {
      frame.number_ok = read_digits(line + 1, kMaxLineNumber, &frame.number, &end);
    }
  }
  uint8_t checksum = 0;  // XOR of every byte before '*' (the RepRap host convention)
  for (char* p = line; *p != '\0'; ++p) {
    if (*p != '*') {
      checksum ^= static_cast<uint8_t>(*p);
      continue;
    }
    frame.has_checksum = true;
    *p = '\0';
    for (char* q = p; q != frame.command && q[-1] == ' ';) *--q = '\0';  // "G28 *71" -> "G28"
    int32_t sent = -1;
    char* end = nullptr;
    frame.checksum_ok = read_digits(p + 1, 255, &sent, &end) && *end == '\0' && sent == checksum;
    break;
  }
  return frame;
}

// The plain acknowledgement, one copy in flash for its four senders.
const FlashText* ok_text() { return GCODE_TEXT("ok\n"); }

bool is_m(const Command& cmd, uint16_t code) { return cmd.letter == 'M' && cmd.code == code; }

// Only M112 (stop) and M108 (cancel the wait) lines pass while M109 waits.
bool passes_wait(char* line) {
  Command cmd;
  return cmd.parse(after_line_number(line)) && (is_m(cmd, 112) || is_m(cmd, 108));
}

}  // namespace

void Interpreter::feed(char byte) {
  if (held_) return;  // contract: the main loop stops feeding while accepting() is false
  const LineAssembler::Event event = line_.feed(byte);
  // "Format error" is among the words hosts (OctoPrint) read as a transmission error (a resend
  // follows, or nothing was lost), not as a firmware fault. A line without a number has no
  // number to resend: it gets the Error and its "ok" (the host's ok count stays in step).
  if (event == LineAssembler::Event::kOverflow) {
    reject_line(line_.numbered(), GCODE_TEXT("Format error: line too long"));
  } else if (event == LineAssembler::Event::kControlChar) {
    reject_line(line_.numbered(), GCODE_TEXT("Format error: control character"), line_.bad_byte());
  } else if (event == LineAssembler::Event::kLine) {
    if (waiting() && !passes_wait(line_.text())) {
      held_ = true;  // processed when the wait ends
      return;
    }
    process_line(line_.text());
  }
}

void Interpreter::input_lost() {
  // Bytes are gone between the previous byte and the next: the line they belonged to is
  // discarded whole. Numbered, the host resends from the first line not accepted.
  if (line_.lose()) reject_line(line_.numbered(), GCODE_TEXT("Format error: serial input lost"));
}

void Interpreter::urgent(Urgent kind) {
  if (kind == Urgent::kStop) return emergency_stop();
  if (kind != Urgent::kCancelWait) return;
  machine_.cancel_heating();  // an M303 in progress ends, heater off
  // The M109's "ok" (and the held line, if any). A machine command (M500) is not cancelled: it
  // finishes on its own, well within a second.
  if (waiting() && wait_ != Wait::kMachine) finish_wait();
}

void Interpreter::process_line(char* line) {
  const LineFrame frame = frame_line(line);
  Command cmd;
  const bool parsed = cmd.parse(frame.command);
  // A stop must not be lost to a transmission error; executing it twice on resend is harmless.
  // urgent() has normally stopped and said so already (a latched fault holds the heater off):
  // the line then only gets its "ok".
  if (parsed && is_m(cmd, 112) && !machine_.heater_status().fault) emergency_stop();

  if (frame.numbered && !frame.number_ok) return request_resend(GCODE_TEXT("Bad line number"));
  if (frame.numbered && !frame.has_checksum) {
    return request_resend(GCODE_TEXT("No checksum with line number"));
  }
  if (!frame.numbered && frame.has_checksum) {
    return request_resend(GCODE_TEXT("No line number with checksum"));
  }
  if (frame.has_checksum && !frame.checksum_ok) return request_resend(GCODE_TEXT("checksum mismatch"));
  // M110 sets the number, so it is exempt from the sequence check (as hosts expect).
  // Unsigned: the line after kMaxLineNumber does not exist, and the sum must not overflow.
  const uint32_t expected = static_cast<uint32_t>(last_line_) + 1u;
  if (frame.numbered && static_cast<uint32_t>(frame.number) != expected && !(parsed && is_m(cmd, 110))) {
    return request_resend(GCODE_TEXT("Line number is not last line number+1"));
  }
  if (frame.numbered) last_line_ = frame.number;

  const char* text = frame.command;
  while (*text == ' ') ++text;
  if (*text == '\0') {  // "N7*xx": a numbered empty line
    out_.print(ok_text());
    return;
  }
  if (!parsed) {
    echo_unknown(text);
    out_.print(ok_text());
    return;
  }
  execute(cmd);
}

void Interpreter::execute(const Command& cmd) {
  const bool was_waiting = waiting();
  const Handler handler = handler_for(cmd);
  ok_sent_ = false;
  if (handler != nullptr) {
    if (cmd.valid(out_)) (this->*handler)(cmd);
  } else if (!machine_.handle_command(cmd, out_)) {
    echo_unknown(cmd.typed);
  }
  if (!was_waiting && machine_.command_pending()) wait_ = Wait::kMachine;  // M500: ok when written
  if (ok_sent_ || (waiting() && !was_waiting)) return;  // M105; M109/M500: finish_wait() sends it
  out_.print(ok_text());
}

void Interpreter::echo_unknown(const char* typed) {
  out_.print(GCODE_TEXT("echo:Unknown command: \""));
  out_.write(typed);
  out_.print(GCODE_TEXT("\"\n"));
}

void Interpreter::emergency_stop() {
  machine_.emergency_stop();
  out_.print(GCODE_TEXT("Error:Emergency stop (M112): heater off until M999\n"));
}

void Interpreter::reject_line(bool numbered, const FlashText* reason, int16_t bad_byte) {
  // Hosts resend everything from the requested line; only numbered lines advance last_line_.
  // Every reason names "line number", "checksum" or "format error": OctoPrint treats such
  // errors as transmission errors awaiting the Resend instead of firmware faults.
  out_.begin_error();
  out_.print(reason);
  if (bad_byte >= 0) {
    out_.print(GCODE_TEXT(" 0x"));
    for (int8_t shift = 4; shift >= 0; shift -= 4) {
      const char digit = static_cast<char>((bad_byte >> shift) & 0xF);
      out_.write_char(static_cast<char>(digit < 10 ? '0' + digit : 'A' + digit - 10));
    }
  }
  if (!numbered) {
    out_.print(GCODE_TEXT(", line discarded\nok\n"));
    return;
  }
  out_.print(GCODE_TEXT(", Last Line: "));
  out_.write_int(last_line_);
  out_.print(GCODE_TEXT("\nResend: "));
  out_.write_uint(static_cast<uint32_t>(last_line_) + 1u);
  out_.print(GCODE_TEXT("\nok\n"));
}

void Interpreter::poll(uint32_t now_ms) {
  now_ms_ = now_ms;
  machine_.background(out_);
  const uint32_t since_report_ms = now_ms - last_report_ms_;  // unsigned: wrap-safe
  if (wait_ == Wait::kMachine) {
    if (!machine_.command_pending()) finish_wait();
    return;
  }
  if (waiting()) {
    const HeaterStatus status = machine_.heater_status();
    const int32_t error_q8 = status.temp_q8 - status.target_q8;
    // A target of 0 (heater off) ends either kind of wait: M109 R0 would otherwise wait for the
    // hotend to cool to 0 °C, which never happens.
    const bool reached = error_q8 >= -kWaitWindowQ8;
    if (status.fault || status.target_q8 == 0 || (reached && (wait_ == Wait::kHeating || error_q8 <= kWaitWindowQ8))) {
      finish_wait();
    } else if (since_report_ms >= kWaitReportMs) {
      write_temperatures();
      out_.end_line();
      last_report_ms_ = now_ms;
    }
    return;
  }
  if (autoreport_s_ != 0 && since_report_ms >= autoreport_s_ * 1000ul) {
    write_temperatures();
    out_.end_line();
    last_report_ms_ = now_ms;
  }
}

void Interpreter::finish_wait() {
  wait_ = Wait::kNone;
  out_.print(ok_text());
  if (held_) {
    held_ = false;
    process_line(line_.text());
  }
}

void Interpreter::write_temperatures() {
  // "T:210.00 /210.00 @:87": the format OctoPrint and Pronterface parse (@ = power 0-255).
  const HeaterStatus status = machine_.heater_status();
  out_.print(GCODE_TEXT("T:"));
  out_.write_q8(status.temp_q8);
  out_.print(GCODE_TEXT(" /"));
  out_.write_q8(status.target_q8);
  out_.print(GCODE_TEXT(" @:"));
  out_.write_uint(status.duty_q16 >> 8);
}

}  // namespace gcode
