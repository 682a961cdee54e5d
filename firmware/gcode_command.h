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

  // Parses the command word at the start of `text` ("M104 S210", "m104s210"): a letter and an
  // integer code, followed by a blank, the end or a parameter letter. False if there is none.
  bool parse(const char* text);
  // Checks every parameter word's syntax (letter + number); prints the Error line and returns
  // false on the first bad one. The layer calls it before its own handlers; a Machine handling
  // extension commands should call it too.
  bool valid(Output& out) const;

  bool has(char letter) const;
  // Reads parameter `p` as round(value × 2^frac_bits) (frac_bits 0..16; 0 = integer, a
  // fraction is then an error) into *value if present; absent: *value untouched, returns true.
  // Malformed, fractional integer or outside [lo, hi]: prints "Error:M104 S out of range 0..275"
  // ("must be an integer in" for frac_bits 0) and returns false. Nothing else is written.
  bool fixed(char p, uint8_t frac_bits, int32_t lo, int32_t hi, int32_t* value, Output& out) const;
  bool q16(char p, int32_t lo_q16, int32_t hi_q16, int32_t* value_q16, Output& out) const {
    return fixed(p, 16, lo_q16, hi_q16, value_q16, out);
  }
  // fixed(p, 0, lo, hi, ...) for bounds within int16 (every integer parameter but line numbers and
  // M311's fields): one call with narrower constants at each of its ~12 call sites.
  bool integer(char p, int16_t lo, int16_t hi, int32_t* value, Output& out) const;
  // Prints "Error:M104: missing S" and returns false when `p` is absent.
  bool require(char p, Output& out) const;
  // "Error:M104" — the start of its error lines.
  void begin_error(Output& out) const;
  // The number token of parameter `p` (first occurrence), nullptr if absent.
  const char* find(char p) const;
};

}  // namespace gcode
