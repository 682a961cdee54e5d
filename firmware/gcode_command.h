// One parsed command line: the command word (G/M/T/D + integer code) and its parameters,
// which stay as text in the line buffer and are converted on demand. Word syntax has been
// validated before a handler sees the Command, so handlers only check presence and range.
#pragma once
#include <stdint.h>

#include "firmware/gcode_output.h"

namespace gcode {

struct Command {
  char letter = 0;                // 'G', 'M', 'T' or 'D' (upper-cased)
  uint16_t code = 0;              // e.g. 104 for M104
  const char* params = nullptr;   // "S210.5 T0": words of a letter and a number, space separated
  const char* typed = nullptr;    // the command as typed (without N, checksum, comment)

  bool has(char letter) const;
  // Reads parameter `p` (a decimal number, at most 32767.99998) as Q16 into *value_q16 if present
  // (absent: *value_q16 untouched, returns true). Out of [lo_q16, hi_q16]: prints
  // "Error:M104 S out of range 0..275" and returns false. Nothing else is written.
  bool q16(char p, int32_t lo_q16, int32_t hi_q16, int32_t* value_q16, Output& out) const;
  // Same for integer parameters (line numbers, indices); a fraction is an error.
  bool integer(char p, int32_t lo, int32_t hi, int32_t* value, Output& out) const;
  // Prints "Error:M104: missing S" and returns false when `p` is absent.
  bool require(char p, Output& out) const;
  // "M104" — for error lines.
  void write_name(Output& out) const;
};

}  // namespace gcode
