#include "firmware/gcode_line.h"

namespace gcode {

LineAssembler::Event LineAssembler::feed(char byte) {
  if (byte == '\n' || byte == '\r') {
    const bool overflowed = overflow_;
    while (len_ != 0 && buf_[len_ - 1] == ' ') --len_;  // "M105 ;poll" -> "M105"
    buf_[len_] = '\0';
    const bool empty = len_ == 0;
    len_ = 0;  // text() stays valid until the next byte arrives
    in_comment_ = false;
    overflow_ = false;
    if (overflowed) return Event::kOverflow;
    return empty ? Event::kNone : Event::kLine;  // empty and comment-only lines get no reply
  }
  if (byte == ';') in_comment_ = true;
  if (in_comment_ || overflow_) return Event::kNone;
  if (byte == '\t') byte = ' ';
  if (static_cast<uint8_t>(byte) < 0x20 || byte == 0x7F) return Event::kNone;  // line noise
  if (len_ == 0 && byte == ' ') return Event::kNone;  // leading blanks
  if (len_ >= kCapacity - 1) {
    overflow_ = true;  // keep discarding until the end of the line, then report once
    len_ = 0;
    return Event::kNone;
  }
  buf_[len_++] = byte;
  return Event::kNone;
}

}  // namespace gcode
