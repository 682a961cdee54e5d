// Assembles received bytes into one line: bounded buffer, ';' comments dropped, CR or LF ends
// the line, control characters ignored. An overlong line is reported as such, never truncated
// into a different command.
#pragma once
#include <stdint.h>

namespace gcode {

class LineAssembler {
 public:
  static constexpr uint8_t kCapacity = 96;  // bytes including the terminating NUL

  enum class Event : uint8_t { kNone, kLine, kOverflow };
  // kLine: text() holds a complete, non-empty line (trailing blanks removed) until the next
  // feed(), which starts a new line.
  // kOverflow: a line longer than kCapacity - 1 characters was discarded.
  Event feed(char byte);
  char* text() { return buf_; }

 private:
  char buf_[kCapacity] = {};
  uint8_t len_ = 0;
  bool in_comment_ = false;
  bool overflow_ = false;
};

}  // namespace gcode
