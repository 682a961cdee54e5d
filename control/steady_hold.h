// The hotend's static gain from a steady hold (issue 7, hot starts): while a controller holds a
// constant target, every reading within ±1 °C of it and the part fan off, the mean duty over a
// window of 512 control periods (65.5 s at 128 ms) and the mean reading give
// K = (reading − 25 °C) / duty, the kelvin per unit duty that M303 needs for its steady duty
// ū = (S − 25 °C)/K. A tune started hot otherwise takes K from a short pulse on a decaying
// baseline, which reads it up to 2 × off behind a sensor lag (docs/autotune.md, "A steady hold").
// 25 °C is the ambient M303 assumes on a hot start: an error in it cancels to first order in ū
// (ū = duty · (S − a)/(reading − a)). Integer-only, portable (AVR and host); fed once per control
// period, outside the timed step.
#pragma once

#include <stdint.h>

namespace control {

class SteadyHold {
 public:
  static constexpr uint16_t kWindowPeriods = 512;  // 2^9: the means are shifts
  static constexpr int32_t kBandQ8 = 256;          // every reading within ±1 °C of the target
  static constexpr uint16_t kMinDutyQ16 = 1311;    // 2 %: below it K is mostly rounding
  static constexpr int32_t kAmbientQ8 = 25L * 256;  // as control::Autotune assumes when hot
  // K 50..4,000 °C per unit duty (the bank's hotends: 428..1,176): outside, no K.
  static constexpr uint16_t kMinGainQ4 = 50u * 16u;
  static constexpr uint16_t kMaxGainQ4 = 4000u * 16u;

  constexpr SteadyHold() = default;

  // One control period: the target (°C × 256, 0 = off), the reading, the duty that ran during the
  // period just ended (65535 = 100 %) and the part fan's duty (0..255).
  void update(int32_t target_q8, int32_t measured_q8, uint16_t duty_q16, uint8_t fan_duty);
  // Forgets the held K (M303 has used it).
  void reset() { gain_q4_ = 0; }

  // K (°C × 256 per unit duty) from the last complete steady window; 0 if there is none.
  int32_t static_gain_q8() const { return static_cast<int32_t>(gain_q4_) << 4; }

 private:
  int16_t target_q6_ = 0;    // the window's target (°C × 64: targets ≤ 275 °C fit; 2 B of RAM)
  int32_t sum_temp_q8_ = 0;  // Σ readings over the window (< 2^9 × 2^17)
  uint32_t sum_duty_ = 0;    // Σ duty_q16 (< 2^9 × 2^16)
  uint16_t periods_ = 0;
  uint16_t gain_q4_ = 0;     // K of the last complete window, °C × 16 per unit duty (0: none)
};

}  // namespace control
