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

namespace {

uint32_t pow5(uint8_t n) {
  uint32_t p = 1;
  while (n-- != 0) p *= 5u;
  return p;
}

// frac / 2^frac_bits in units of 10^-decimals, rounded to nearest: frac · 5^d · 2^d / 2^fb, so
// the product frac · 5^d < 2^16 · 3125 < 2^28 fits for every decimals ≤ 5.
// noinline: write_fixed and write_exact share one copy (24 B of AVR flash).
__attribute__((noinline)) uint32_t decimal_units(uint32_t frac, uint8_t frac_bits, uint8_t decimals) {
  const uint32_t p5 = pow5(decimals);
  if (frac_bits <= decimals) return (frac * p5) << (decimals - frac_bits);
  const uint8_t shift = static_cast<uint8_t>(frac_bits - decimals);
  return (frac * p5 + (1ul << (shift - 1u))) >> shift;
}

}  // namespace

void Output::write_fixed(int32_t value, uint8_t frac_bits, uint8_t decimals) {
  uint32_t scale = 1;  // 10^decimals
  for (uint8_t i = 0; i < decimals; ++i) scale *= 10u;
  const uint32_t magnitude = value < 0 ? 0u - static_cast<uint32_t>(value) : static_cast<uint32_t>(value);
  uint32_t whole = magnitude >> frac_bits;
  uint32_t decimal = decimal_units(magnitude & ((1ul << frac_bits) - 1u), frac_bits, decimals);
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

void Output::write_exact(int32_t value, uint8_t frac_bits) {
  // The fewest decimals (2 up) whose rounded text parses back (number_to_fixed rounds to the
  // nearest 2^-frac_bits) to the same fraction: at most 3 for Q8, 5 for Q16 (10^-d / 2 <
  // 2^-(frac_bits + 1)). units · 2^(fb − d) ≤ 10^5 · 2^14 < 2^31.
  const uint32_t magnitude = value < 0 ? 0u - static_cast<uint32_t>(value) : static_cast<uint32_t>(value);
  const uint32_t frac = magnitude & ((1ul << frac_bits) - 1u);
  uint8_t decimals = 2;
  for (; decimals < 5 && decimals < frac_bits; ++decimals) {
    const uint32_t p5 = pow5(decimals);
    const uint32_t back = ((decimal_units(frac, frac_bits, decimals) << (frac_bits - decimals)) + p5 / 2u) / p5;
    if (back == frac) break;
  }
  write_fixed(value, frac_bits, decimals);
}

// noinline: its three callers each had the test and the call inlined.
__attribute__((noinline)) void Output::refusal_line(const FlashText* reason) {
  if (reason != nullptr) error_line(reason);
}

void Output::begin_error() { print(GCODE_TEXT("Error:")); }

void Output::error_line(const FlashText* reason) {
  begin_error();
  print(reason);
  end_line();
}

}  // namespace gcode
