// Where replies go, and the number formatting every reply needs — without printf, which would
// add kilobytes of flash on AVR. The firmware implements the two virtual methods on its UART
// transmit ring; the host tests on a std::string.
#pragma once
#include <stdint.h>

#include "firmware/gcode_text.h"

namespace gcode {

class Output {
 public:
  virtual void write_char(char c) = 0;
  // `text` is NUL-terminated in program memory on AVR (read with pgm_read_byte), plain on host.
  virtual void write_flash(const FlashText* text) = 0;

  void print(const FlashText* text);  // = write_flash(); a plain call is smaller on AVR
  void write(const char* ram_text);
  void write_uint(uint32_t value);
  void write_int(int32_t value);
  // value / 2^frac_bits with `decimals` (0..5) digits after the point, rounded to nearest
  // (halves away from zero), e.g. write_fixed(53759, 8, 2) -> "210.00". frac_bits 0..16.
  void write_fixed(int32_t value, uint8_t frac_bits, uint8_t decimals);
  void write_q8(int32_t value_q8) { write_fixed(value_q8, 8, 2); }  // temperatures
  // Two decimals, or more (up to 3 for Q8, 5 for Q16) where fewer would not read back as the
  // same value: what M503 prints must replay exactly (a tuned Ki of 0.0091 printed as 0.01 is
  // 10 % off, and a gain just under the fuzzy schedule's limit, rounded up, was refused on
  // replay), while typed values such as D20.7 or P22.2 still print as typed. frac_bits 8..16.
  void write_exact(int32_t value, uint8_t frac_bits);
  void write_q16(int32_t value_q16) { write_exact(value_q16, 16); }  // gains
  void end_line() { write_char('\n'); }
  // "Error:" + text + "\n" — the reply for refused input (see Machine's refusal reasons).
  void error_line(const FlashText* reason);
  // error_line(reason) unless reason is nullptr (the machine's "accepted").
  void refusal_line(const FlashText* reason);
  // "Error:" alone, for error lines built from parts (one copy of the text in flash).
  void begin_error();

 protected:
  ~Output() = default;  // never deleted through this interface (no heap in the firmware)
};

}  // namespace gcode
