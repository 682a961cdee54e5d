#include "firmware/gcode_emergency_parser.h"

namespace gcode {
namespace {

constexpr uint16_t kCodeLimit = 1000;  // above every code recognised; keeps code_ * 10 in 16 bits

bool is_end(uint8_t b) { return b == '\n' || b == '\r'; }
bool is_space(uint8_t b) { return b == ' ' || b == '\t'; }
bool is_digit_byte(uint8_t b) { return b >= '0' && b <= '9'; }
bool is_letter_byte(uint8_t b) { return (b | 0x20) >= 'a' && (b | 0x20) <= 'z'; }

// What may follow the command word in a line the parser accepts ("M112", "M112 ", "M112*64",
// "M112;stop", "M108S1"); a digit never gets here.
bool ends_word(uint8_t b) { return is_end(b) || is_space(b) || is_letter_byte(b) || b == '*' || b == ';'; }

}  // namespace

Urgent EmergencyParser::feed(uint8_t byte) {
  if (state_ == State::kCode) {
    if (is_digit_byte(byte)) {
      code_ = code_ >= kCodeLimit ? kCodeLimit : static_cast<uint16_t>(code_ * 10u + (byte - '0'));
      return Urgent::kNone;
    }
    const uint16_t code = code_;
    state_ = is_end(byte) ? State::kLineStart : State::kIgnore;
    if (!ends_word(byte)) return Urgent::kNone;
    if (code == 112) return Urgent::kStop;
    if (code == 108) return Urgent::kCancelWait;
    return Urgent::kNone;
  }
  if (is_end(byte)) {
    state_ = State::kLineStart;
    return Urgent::kNone;
  }
  switch (state_) {
    case State::kLineStart:
      if (is_space(byte)) return Urgent::kNone;
      if ((byte | 0x20) == 'n') {
        state_ = State::kLineNumber;
        return Urgent::kNone;
      }
      break;
    case State::kLineNumber:
      if (is_digit_byte(byte)) return Urgent::kNone;
      if (is_space(byte)) {
        state_ = State::kAfterNumber;
        return Urgent::kNone;
      }
      break;
    case State::kAfterNumber:
      if (is_space(byte)) return Urgent::kNone;
      break;
    default:  // kIgnore: the rest of the line
      return Urgent::kNone;
  }
  // The command word may start here; anything else makes the line uninteresting.
  if ((byte | 0x20) == 'm') {
    state_ = State::kCode;
    code_ = 0;
  } else {
    state_ = State::kIgnore;
  }
  return Urgent::kNone;
}

}  // namespace gcode
