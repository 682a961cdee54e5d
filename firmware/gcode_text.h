// Constant reply text that lives in program memory on AVR (RAM is 8 KB / 16 KB and every
// string literal would otherwise be copied into it at start-up) and is plain const char on the host.
// This is the only place in the G-code layer that tells the two apart; it needs no AVR header.
#pragma once

namespace gcode {

// Opaque marker: a NUL-terminated text in program memory (AVR) or ordinary memory (host).
// Never dereference it directly; only Output::write_flash() reads it (firmware: pgm_read_byte).
struct FlashText;

}  // namespace gcode

#if defined(__AVR__)
#define GCODE_PROGMEM __attribute__((__progmem__))
#else
#define GCODE_PROGMEM
#endif

// GCODE_TEXT("literal") -> const gcode::FlashText*, usable inside functions (like avr-libc PSTR).
#define GCODE_TEXT(literal)                                                   \
  (__extension__({                                                            \
    static const char gcode_text_[] GCODE_PROGMEM = (literal);                \
    reinterpret_cast<const ::gcode::FlashText*>(&gcode_text_[0]);             \
  }))
