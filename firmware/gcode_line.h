// Assembles received bytes into one line: bounded buffer, ';' comments dropped, CR or LF ends
// the line. A line that cannot be trusted — too long, holding a control character, or broken
// by lost input — is discarded whole and reported, never truncated or cleaned into a
// different command (`M10<DEL>4 S2<SOH>10` must not become `M104 S210`).
#pragma once
#include <stdint.h>

namespace gcode {

// Line numbers a host may send (N0..N2147483647). M110 sets the last line to at most one less,
// so the line after it can always be sent.
constexpr int32_t kMaxLineNumber = 0x7FFFFFFF;

class LineAssembler {
 public:
  static constexpr uint8_t kCapacity = 96;  // bytes including the terminating NUL

  enum class Event : uint8_t { kNone, kLine, kOverflow, kControlChar };
  // kLine: text() holds a complete, non-empty line (trailing blanks removed) until the next
  // feed(), which starts a new line.
  // kOverflow: a line longer than kCapacity - 1 characters was discarded.
  // kControlChar: a line holding a control character (not CR, LF or TAB; outside its
  // comment) was discarded; bad_byte() is the first one.
  // For both, numbered() tells whether the discarded line began with N (a line number).
  Event feed(char byte);
  char* text() { return buf_; }
  bool numbered() const { return numbered_; }
  uint8_t bad_byte() const { return bad_byte_; }

  // Input was lost here. Discards the line in progress and everything up to the next CR/LF
  // (the rest of a line whose start is gone), with no event. Returns false when it was
  // already discarding for an earlier loss (one report per damaged stretch); numbered() then
  // tells whether the line in progress had begun with N.
  bool lose();

 private:
  enum class Damage : uint8_t { kNone, kOverflow, kControlChar, kLost };
  void start_line();

  char buf_[kCapacity] = {};
  uint8_t len_ = 0;
  uint8_t bad_byte_ = 0;
  Damage damage_ = Damage::kNone;
  bool in_comment_ = false;
  bool started_ = false;   // a character other than a blank or control byte has arrived
  bool numbered_ = false;  // ... and the first one was N
};

}  // namespace gcode
