#include "firmware/gcode_output.h"

namespace gcode {

void Output::print(const FlashText* text) { write_flash(text); }

void Output::write(const char* ram_text) {
  while (*ram_text != '\0') write_char(*ram_text++);
}

void Output::write_uint(uint32_t value) {
  char digits[10];  // 4294967295 has 10 digits
  uint8_t count = 0;
  do {
    digits[count++] = static_cast<char>('0' + value % 10u);
    value /= 10u;
  } while (value != 0);
  while (count != 0) write_char(digits[--count]);
}

void Output::write_int(int32_t value) {
  if (value < 0) write_char('-');
  // Negate in unsigned arithmetic: INT32_MIN has no positive int32 counterpart.
  write_uint(value < 0 ? 0u - static_cast<uint32_t>(value) : static_cast<uint32_t>(value));
}

void Output::write_fixed(int32_t value, uint8_t frac_bits, uint8_t decimals) {
  uint32_t scale = 1;  // 10^decimals
  for (uint8_t i = 0; i < decimals; ++i) scale *= 10u;
  const uint32_t magnitude = value < 0 ? 0u - static_cast<uint32_t>(value) : static_cast<uint32_t>(value);
  uint32_t whole = magnitude >> frac_bits;
  const uint32_t frac = magnitude & ((1ul << frac_bits) - 1u);
  const uint32_t half = frac_bits != 0 ? (1ul << (frac_bits - 1u)) : 0u;
  // frac < 2^16 and scale <= 10^4: the product stays below 2^32.
  uint32_t decimal = (frac * scale + half) >> frac_bits;
  if (decimal >= scale) {  // rounded up into the next unit, e.g. 209.996 -> 210.00
    ++whole;
    decimal -= scale;
  }
  if (value < 0 && (whole != 0 || decimal != 0)) write_char('-');  // no "-0.00"
  write_uint(whole);
  if (decimals == 0) return;
  write_char('.');
  for (uint32_t digit = scale / 10u; digit != 0; digit /= 10u) {
    write_char(static_cast<char>('0' + (decimal / digit) % 10u));
  }
}

void Output::error_line(const FlashText* reason) {
  print(GCODE_TEXT("Error:"));
  print(reason);
  end_line();
}

}  // namespace gcode
