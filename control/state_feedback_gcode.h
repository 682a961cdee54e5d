// The M311 text form of StateFeedbackConstants (contract: docs/controllers.md, "M-code reference"), shared by
// the firmware (parse, M503), the design tool and the simulator so that all three agree:
//   fields in struct order, arrays at full capacity, flat index 0..kSfFieldCount−1;
//   "M311 I<first> A<v> B<v> ... H<v>" writes fields first..first+7; "M311 W1" commits.
// Header-only and portable (no stdio, no float): the firmware formats with it too.
#pragma once

#include <stddef.h>
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

// Element type and count of a member (T or T[N]); no <type_traits> in avr-gcc's toolchain.
template <class T> struct Elements { using type = T; static constexpr uint8_t count = 1; };
template <class T, unsigned N> struct Elements<T[N]> { using type = T; static constexpr uint8_t count = N; };

constexpr SfFieldType type_of(const uint8_t*) { return SfFieldType::kU8; }
constexpr SfFieldType type_of(const int16_t*) { return SfFieldType::kI16; }
constexpr SfFieldType type_of(const int32_t*) { return SfFieldType::kI32; }

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

// One run of consecutive fields of one type: a member (count 1) or an array member.
struct SfRun {
  uint8_t offset;  // offsetof(StateFeedbackConstants, member)
  uint8_t count;
  SfFieldType type;
};

#define SF_RUN(member)                                                                            \
  SfRun {                                                                                         \
    static_cast<uint8_t>(offsetof(StateFeedbackConstants, member)),                               \
        sf_gcode_detail::Elements<decltype(StateFeedbackConstants::member)>::count,               \
        sf_gcode_detail::type_of(                                                                 \
            static_cast<const sf_gcode_detail::Elements<decltype(StateFeedbackConstants::member)>::type*>(nullptr)) \
  }

// Every member in struct order: the flat index walks these runs (a table rather than a chain
// of inlined per-member steps: ~250 B less AVR flash).
static_assert(sizeof(StateFeedbackConstants) <= 256, "run offsets are bytes");
constexpr uint8_t kSfRunCount = 26;
struct SfRuns {
  SfRun run[kSfRunCount];
};
constexpr SfRuns kSfRuns = {{SF_RUN(n), SF_RUN(output_mask), SF_RUN(delay), SF_RUN(decimation), SF_RUN(input_shift),
                             SF_RUN(ambient_q8), SF_RUN(phi_diag), SF_RUN(phi_off), SF_RUN(phi_col), SF_RUN(gamma_a),
                             SF_RUN(gamma_b), SF_RUN(phi_shift), SF_RUN(obs_gain), SF_RUN(obs_shift), SF_RUN(fb_gain),
                             SF_RUN(ff_gain), SF_RUN(bias_gain), SF_RUN(ctrl_shift), SF_RUN(fir), SF_RUN(fir_shift),
                             SF_RUN(fan_gain), SF_RUN(fan_shift), SF_RUN(ss_share), SF_RUN(ss_share_shift),
                             SF_RUN(inv_gain), SF_RUN(inv_gain_shift)}};
#undef SF_RUN

constexpr uint8_t sf_run_fields(uint8_t i) {
  return i == kSfRunCount ? 0 : static_cast<uint8_t>(kSfRuns.run[i].count + sf_run_fields(static_cast<uint8_t>(i + 1)));
}
static_assert(sf_run_fields(0) == kSfFieldCount, "kSfRuns covers every field once");

// Run i of kSfRuns: read from program memory on AVR (firmware/state_feedback_runs_flash.cpp,
// 78 bytes of RAM otherwise), from kSfRuns on the host (control/state_feedback_runs.cpp).
SfRun sf_run(uint8_t i);

// Field `index` of k: its address and type (address nullptr when index ≥ kSfFieldCount).
inline SfField sf_field(StateFeedbackConstants& k, uint8_t index) {
  for (uint8_t i = 0; i < kSfRunCount; ++i) {
    const SfRun r = sf_run(i);
    if (index < r.count) {
      const uint8_t size = r.type == SfFieldType::kU8 ? 1 : (r.type == SfFieldType::kI16 ? 2 : 4);
      return SfField{reinterpret_cast<uint8_t*>(&k) + r.offset + index * size, r.type};
    }
    index = static_cast<uint8_t>(index - r.count);
  }
  return SfField{nullptr, SfFieldType::kU8};
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
// field, zeros included) and "M311 W1", told to a sink: begin_line(first) starts
// "M311 I<first>", field(letter, value) adds " <letter><value>", end_line() ends it, and
// commit_line() is the "M311 W1" line. (The firmware's sink prints straight to the serial
// output: no line buffer, no second integer formatter.)
template <class Sink>
void write_state_feedback_lines(const StateFeedbackConstants& k, Sink& sink) {
  for (uint8_t first = 0; first < kSfFieldCount; first = static_cast<uint8_t>(first + kSfFieldsPerLine)) {
    sink.begin_line(first);
    for (uint8_t j = 0; j < kSfFieldsPerLine && first + j < kSfFieldCount; ++j)
      sink.field(static_cast<char>('A' + j), sf_get(k, static_cast<uint8_t>(first + j)));
    sink.end_line();
  }
  sink.commit_line();
}

// The same lines as text: put_line(const char*) gets each line without newline.
template <class PutLine>
void write_state_feedback_mcode(const StateFeedbackConstants& k, PutLine put_line) {
  struct LineSink {
    PutLine& put_line;
    char line[8 + kSfFieldsPerLine * 13 + 1];  // "M311 I96" + 8 × " A" and up to 11 characters
    char* p;
    void begin_line(uint8_t first) {
      p = line;
      sf_gcode_detail::append(p, "M311 I");
      sf_gcode_detail::append_int(p, first);
    }
    void field(char letter, int32_t value) {
      *p++ = ' ';
      *p++ = letter;
      sf_gcode_detail::append_int(p, value);
    }
    void end_line() {
      *p = '\0';
      put_line(static_cast<const char*>(line));
    }
    void commit_line() { put_line("M311 W1"); }
  };
  LineSink sink{put_line, {}, nullptr};
  write_state_feedback_lines(k, sink);
}

}  // namespace control
