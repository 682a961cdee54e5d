// Recognises M112 (emergency stop) and M108 (cancel the wait) in the raw byte stream, before
// the line queue, so a full RX ring, a line held behind an M109 or a running M303 cannot delay
// them (Marlin's EMERGENCY_PARSER does the same; there it acts at the end of the line, here as
// soon as the command word ends). Runs inside the UART RX interrupt: a few bytes of state,
// straight-line code, no G-code tables.
//
// Grammar (a superset of what the line parser accepts for these words, so every M108/M112 line
// it executes was seen here first): at the start of a line, blanks, an optional "N<digits>"
// and blanks, then M or m, digits (leading zeros allowed), ended by a blank, tab, CR/LF, a
// letter, '*' or ';'. Anything else on the line is ignored until CR or LF.
//
// M410 is left out on purpose: in Marlin it stops motion and leaves the heaters on; this board
// has no motion, and turning it into a heater kill would change what hosts expect of it.
#pragma once
#include <stdint.h>

namespace gcode {

enum class Urgent : uint8_t { kNone, kCancelWait, kStop };  // -, M108, M112

class EmergencyParser {
 public:
  // One received byte; returns the command whose word this byte ended, or kNone.
  Urgent feed(uint8_t byte);
  // Bytes were lost before the next one: whether it starts a line is unknown. Assume it does,
  // so a stop right after the loss is still caught (a false start is far less likely).
  void lost() { state_ = State::kLineStart; }

 private:
  enum class State : uint8_t { kLineStart, kLineNumber, kAfterNumber, kCode, kIgnore };
  State state_ = State::kLineStart;
  uint16_t code_ = 0;  // saturates at kCodeLimit: no code of interest is that long
};

}  // namespace gcode
