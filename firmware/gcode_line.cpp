#include "firmware/gcode_line.h"

namespace gcode {

void LineAssembler::start_line() {
  len_ = 0;  // text() stays valid until the next byte arrives
  in_comment_ = false;
  damage_ = Damage::kNone;
  started_ = false;
  numbered_ = false;
}

LineAssembler::Event LineAssembler::feed(char byte) {
  if (byte == '\n' || byte == '\r') {
    while (len_ != 0 && buf_[len_ - 1] == ' ') --len_;  // "M105 ;poll" -> "M105"
    buf_[len_] = '\0';
    const Damage damage = damage_;
    const bool empty = len_ == 0;
    const bool numbered = numbered_;
    start_line();
    numbered_ = numbered;  // kept for the caller of a discarded line
    if (damage == Damage::kOverflow) return Event::kOverflow;
    if (damage == Damage::kControlChar) return Event::kControlChar;
    if (damage == Damage::kLost) return Event::kNone;  // reported when the loss was seen
    return empty ? Event::kNone : Event::kLine;  // empty and comment-only lines get no reply
  }
  if (byte == ';') in_comment_ = true;
  if (in_comment_) return Event::kNone;  // a comment is not interpreted: its bytes do not matter
  if (byte == '\t') byte = ' ';
  const bool control = static_cast<uint8_t>(byte) < 0x20 || byte == 0x7F;
  if (!started_ && !control && byte != ' ') {
    started_ = true;
    numbered_ = byte == 'N' || byte == 'n';
  }
  if (damage_ != Damage::kNone) return Event::kNone;  // discard until the end of the line
  if (control) {
    damage_ = Damage::kControlChar;
    bad_byte_ = static_cast<uint8_t>(byte);
    return Event::kNone;
  }
  if (len_ == 0 && byte == ' ') return Event::kNone;  // leading blanks
  if (len_ >= kCapacity - 1) {
    damage_ = Damage::kOverflow;  // keep discarding until the end of the line, then report once
    return Event::kNone;
  }
  buf_[len_++] = byte;
  return Event::kNone;
}

bool LineAssembler::lose() {
  const bool new_loss = damage_ != Damage::kLost;
  damage_ = Damage::kLost;
  len_ = 0;
  return new_loss;
}

}  // namespace gcode
