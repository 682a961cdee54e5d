// Constant text for the G-code Output built at compile time from constexpr strings (the
// board's name lives in boards/<board>.h as a `constexpr const char*`, which a PROGMEM array
// cannot point at): copy or join the characters into a char array the compiler fills in.
#pragma once
#include <stdint.h>

#include "firmware/gcode_text.h"

namespace firmware {

template <unsigned N>
struct FlashChars {
  char text[N];
  const gcode::FlashText* flash() const { return reinterpret_cast<const gcode::FlashText*>(text); }
};

constexpr unsigned text_length(const char* s) {
  unsigned n = 0;
  while (s[n] != '\0') ++n;
  return n;
}

// a + b as one NUL-terminated array of N = len(a) + len(b) + 1 characters.
template <unsigned N>
constexpr FlashChars<N> join(const char* a, const char* b) {
  FlashChars<N> out{};
  unsigned i = 0;
  for (unsigned j = 0; a[j] != '\0'; ++j) out.text[i++] = a[j];
  for (unsigned j = 0; b[j] != '\0'; ++j) out.text[i++] = b[j];
  out.text[i] = '\0';
  return out;
}

}  // namespace firmware

// Declares `name` as program-memory text a + b (both constexpr strings).
#define FIRMWARE_FLASH_JOIN(name, a, b)                                                      \
  constexpr auto name##_value =                                                              \
      ::firmware::join<::firmware::text_length(a) + ::firmware::text_length(b) + 1>(a, b);  \
  const decltype(name##_value) name GCODE_PROGMEM = name##_value
