#include "firmware/gcode_command.h"

#include "firmware/gcode_number.h"

namespace gcode {
namespace {

// noinline: LTO inlined it into more than one caller (24 B of AVR flash as a call).
__attribute__((noinline)) const char* skip_blanks(const char* s) {
  while (*s == ' ') ++s;
  return s;
}

bool is_letter(char c) { return to_upper(c) >= 'A' && to_upper(c) <= 'Z'; }

// Range bounds print as "275" when whole, else with two decimals.
void write_bound(int32_t bound, uint8_t frac_bits, Output& out) {
  const bool whole = (bound & ((1l << frac_bits) - 1)) == 0;
  out.write_fixed(bound, frac_bits, whole ? 0 : 2);
}

}  // namespace

bool Command::parse(const char* text) {
  const char* s = skip_blanks(text);
  if (!is_letter(*s) || !is_digit(s[1])) return false;
  const char word_letter = to_upper(*s++);
  uint32_t value = 0;
  while (is_digit(*s)) {
    value = value * 10u + static_cast<uint32_t>(*s++ - '0');
    if (value > 0xFFFFu) return false;
  }
  // Blank, end, a parameter letter ("M104S210") or '*' (when peeking at an unframed line).
  if (!is_blank(*s) && !is_letter(*s) && *s != '*') return false;  // "M104.1", "G1-"
  letter = word_letter;
  code = static_cast<uint16_t>(value);
  params = skip_blanks(s);
  typed = skip_blanks(text);
  return true;
}

bool Command::valid(Output& out) const {
  for (const char* s = skip_blanks(params); *s != '\0';) {
    const char* token = s + 1;
    if (!is_letter(*s) || !number_valid(token)) {
      begin_error(out);
      out.print(GCODE_TEXT(": malformed parameter \""));
      while (!is_blank(*s)) out.write_char(*s++);
      out.write_char('"');
      out.end_line();
      return false;
    }
    while (!is_blank(*s)) ++s;
    s = skip_blanks(s);
  }
  return true;
}

bool Command::has(char p) const { return find(p) != nullptr; }

const char* Command::find(char p) const {
  for (const char* s = skip_blanks(params); *s != '\0';) {
    if (to_upper(*s) == p) return s + 1;
    while (!is_blank(*s)) ++s;
    s = skip_blanks(s);
  }
  return nullptr;
}

bool Command::fixed(char p, uint8_t frac_bits, int32_t lo, int32_t hi, int32_t* value,
                    Output& out) const {
  const char* token = find(p);
  if (token == nullptr) return true;
  int32_t parsed = 0;
  if (number_to_fixed(token, frac_bits, &parsed) && parsed >= lo && parsed <= hi) {
    *value = parsed;
    return true;
  }
  begin_error(out);
  out.write_char(' ');
  out.write_char(p);
  out.print(frac_bits == 0 ? GCODE_TEXT(" must be an integer in ") : GCODE_TEXT(" out of range "));
  write_bound(lo, frac_bits, out);
  out.print(GCODE_TEXT(".."));
  write_bound(hi, frac_bits, out);
  out.end_line();
  return false;
}

__attribute__((noinline)) bool Command::integer(char p, int16_t lo, int16_t hi, int32_t* value, Output& out) const {
  return fixed(p, 0, lo, hi, value, out);
}

bool Command::require(char p, Output& out) const {
  if (has(p)) return true;
  begin_error(out);
  out.print(GCODE_TEXT(": missing "));
  out.write_char(p);
  out.end_line();
  return false;
}

void Command::begin_error(Output& out) const {
  out.begin_error();
  out.write_char(letter);
  out.write_uint(code);
}

}  // namespace gcode
