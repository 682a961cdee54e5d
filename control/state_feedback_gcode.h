// The M311 text form of StateFeedbackConstants (contract: docs/controllers.md, "M-code reference"), shared by
// the firmware (parse, M503), the design tool and the simulator so that all three agree:
//   fields in struct order, arrays at full capacity, flat index 0..kSfFieldCount−1;
//   "M311 I<first> A<v> B<v> ... H<v>" writes fields first..first+7; "M311 W1" commits.
// Header-only and portable (no stdio, no float): the firmware formats with it too.
#pragma once

#include <stdint.h>

#include "control/state_feedback_constants.h"

namespace control {

constexpr uint8_t kSfFieldCount = 6 + 6 * kSfMaxStates + 2 * (kSfMaxStates + 1) + kSfMaxStates + 3 +
                                  kSfMaxDelay + 3 + kSfMaxStates + 3;  // 99
constexpr uint8_t kSfFieldsPerLine = 8;  // value letters A..H

enum class SfFieldType : uint8_t { kU8, kI16, kI32 };

struct SfField {
  void* address;  // nullptr: no such index
  SfFieldType type;
};

namespace sf_gcode_detail {

inline SfFieldType type_of(uint8_t*) { return SfFieldType::kU8; }
inline SfFieldType type_of(int16_t*) { return SfFieldType::kI16; }
inline SfFieldType type_of(int32_t*) { return SfFieldType::kI32; }

// Walks runs of consecutive fields until the index falls inside one.
struct Cursor {
  uint8_t index;
  SfField field;
  template <class T> Cursor& run(T* first, uint8_t count) {
    if (field.address == nullptr) {
      if (index < count) field = SfField{first + index, type_of(first)};
      else index = static_cast<uint8_t>(index - count);
    }
    return *this;
  }
};

inline void append(char*& p, const char* s) { while (*s != '\0') *p++ = *s++; }

inline void append_int(char*& p, int32_t v) {
  char digits[11];
  uint8_t n = 0;
  uint32_t m = v < 0 ? 0u - static_cast<uint32_t>(v) : static_cast<uint32_t>(v);
  do { digits[n++] = static_cast<char>('0' + m % 10u); m /= 10u; } while (m != 0);
  if (v < 0) *p++ = '-';
  while (n != 0) *p++ = digits[--n];
}

}  // namespace sf_gcode_detail

// Field `index` of k: its address and type (address nullptr when index ≥ kSfFieldCount).
inline SfField sf_field(StateFeedbackConstants& k, uint8_t index) {
  sf_gcode_detail::Cursor c{index, SfField{nullptr, SfFieldType::kU8}};
  c.run(&k.n, 1).run(&k.output_mask, 1).run(&k.delay, 1).run(&k.decimation, 1).run(&k.input_shift, 1)
      .run(&k.ambient_q8, 1).run(k.phi_diag, kSfMaxStates).run(k.phi_off, kSfMaxStates)
      .run(k.phi_col, kSfMaxStates).run(k.gamma_a, kSfMaxStates).run(k.gamma_b, kSfMaxStates)
      .run(k.phi_shift, kSfMaxStates).run(k.obs_gain, kSfMaxStates + 1).run(k.obs_shift, kSfMaxStates + 1)
      .run(k.fb_gain, kSfMaxStates).run(&k.ff_gain, 1).run(&k.bias_gain, 1).run(&k.ctrl_shift, 1)
      .run(k.fir, kSfMaxDelay).run(&k.fir_shift, 1).run(&k.fan_gain, 1).run(&k.fan_shift, 1)
      .run(k.ss_share, kSfMaxStates).run(&k.ss_share_shift, 1).run(&k.inv_gain, 1).run(&k.inv_gain_shift, 1);
  return c.field;
}

// The values M311 accepts for a field of this type (ambient_q8: −100..300 °C).
inline void sf_field_range(SfFieldType type, int32_t* lo, int32_t* hi) {
  *lo = type == SfFieldType::kU8 ? 0 : (type == SfFieldType::kI16 ? -32768 : kSfMinAmbientQ8);
  *hi = type == SfFieldType::kU8 ? 255 : (type == SfFieldType::kI16 ? 32767 : kSfMaxAmbientQ8);
}

// Read-only use of the same walk (the address is only read through).
inline int32_t sf_get(const SfField& f);
inline int32_t sf_get(const StateFeedbackConstants& k, uint8_t index) {
  return sf_get(sf_field(const_cast<StateFeedbackConstants&>(k), index));
}

inline int32_t sf_get(const SfField& f) {
  if (f.type == SfFieldType::kU8) return *static_cast<const uint8_t*>(f.address);
  if (f.type == SfFieldType::kI16) return *static_cast<const int16_t*>(f.address);
  return *static_cast<const int32_t*>(f.address);
}

// Precondition: value within sf_field_range(f.type).
inline void sf_set(const SfField& f, int32_t value) {
  if (f.type == SfFieldType::kU8) *static_cast<uint8_t*>(f.address) = static_cast<uint8_t>(value);
  else if (f.type == SfFieldType::kI16) *static_cast<int16_t*>(f.address) = static_cast<int16_t>(value);
  else *static_cast<int32_t*>(f.address) = value;
}

// The canonical upload of k: ceil(kSfFieldCount / 8) lines "M311 I<i> A<v> ... H<v>" (every
// field, zeros included) and "M311 W1". put_line(const char*) gets each line without newline.
template <class PutLine>
void write_state_feedback_mcode(const StateFeedbackConstants& k, PutLine put_line) {
  char line[8 + kSfFieldsPerLine * 13 + 1];  // "M311 I96" + 8 × " A" and up to 11 characters
  for (uint8_t first = 0; first < kSfFieldCount; first = static_cast<uint8_t>(first + kSfFieldsPerLine)) {
    char* p = line;
    sf_gcode_detail::append(p, "M311 I");
    sf_gcode_detail::append_int(p, first);
    for (uint8_t j = 0; j < kSfFieldsPerLine && first + j < kSfFieldCount; ++j) {
      *p++ = ' ';
      *p++ = static_cast<char>('A' + j);
      sf_gcode_detail::append_int(p, sf_get(k, static_cast<uint8_t>(first + j)));
    }
    *p = '\0';
    put_line(static_cast<const char*>(line));
  }
  put_line("M311 W1");
}

}  // namespace control
