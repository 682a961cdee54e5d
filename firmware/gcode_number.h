// Decimal numbers as G-code writes them ("210", "-3.5", ".25", "+1.") converted to fixed point
// without float. A number token runs up to a blank or the end of the string; anything else
// inside it (S2x1, S--1, S1e3, a lone "S") makes the token malformed.
#pragma once
#include <stdint.h>

namespace gcode {

inline bool is_blank(char c) { return c == ' ' || c == '\0'; }
inline bool is_digit(char c) { return c >= '0' && c <= '9'; }
inline char to_upper(char c) { return (c >= 'a' && c <= 'z') ? static_cast<char>(c - 32) : c; }

// True if the token at `s` is [+-](digits[.[digits]] | .digits).
bool number_valid(const char* s);

// round(value × 2^frac_bits) of a valid token (frac_bits 0..16, halves away from zero).
// False, with *value untouched, if the token is malformed, the result's magnitude exceeds
// 0x7FFFFFFF, or frac_bits is 0 and the token has a nonzero fraction (integers stay integers).
bool number_to_fixed(const char* s, uint8_t frac_bits, int32_t* value);

}  // namespace gcode
