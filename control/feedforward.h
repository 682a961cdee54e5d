// Model feedforward for the PID-family controllers (issue 3): the steady duty the hotend's FOPDT
// model (M307) says the target needs, with the part fan's extra heat loss (fan feedforward):
//   duty_ff = (target − 25 °C) / A × (1 + F/100 · fan/255),   clamped to 0..100 %
// A = rise at 100 % duty (°C), F = extra loss at full fan in % of the no-fan loss. Per-step
// work is multiplies only: configure() turns 1/A and F/25,500 into multipliers (the long
// divisions run there, at G-code time). Float-free, portable.
#pragma once

#include <stdint.h>

#include "control/fixed.h"

namespace control {

// The hotend model hosts set with M307 (RepRapFirmware's letters A, C, D; F is ours). All Q8.
struct HotendModel {
  int32_t rise_q8;           // A: °C above ambient at 100 % duty, × 256
  int32_t time_constant_q8;  // C: s × 256 (stored for model-based tools; not used here)
  int32_t dead_time_q8;      // D: s × 256 (likewise)
  int32_t fan_loss_pct_q8;   // F: extra loss at full part fan, % of the no-fan loss, × 256
};

// What M307 accepts (°C, s, %, all Q8).
constexpr int32_t kModelMinRiseQ8 = 10L * 256;
constexpr int32_t kModelMaxRiseQ8 = 2000L * 256;
constexpr int32_t kModelMinTimeConstantQ8 = 1L * 256;
constexpr int32_t kModelMaxTimeConstantQ8 = 3600L * 256;
constexpr int32_t kModelMaxDeadTimeQ8 = 600L * 256;
constexpr int32_t kModelMaxFanLossPctQ8 = 500L * 256;

// The ambient the model's rise is counted from (brief: 25 °C).
constexpr int32_t kFeedforwardAmbientQ8 = 25L * 256;

// hotend40w (issue 2's physical model, E3D-V6 class): A = 40 W / 0.068 W/K; C = 16.7 J/K /
// 0.068 W/K; D = the sensor's 1/0.22 s first-order lag taken as dead time; F = 0.097/0.068 − 1.
// Computed by the compiler (fixed::from_double is constexpr: no float in the image).
constexpr HotendModel kHotend40wModel{fixed::from_double(40.0 / 0.068, 8), fixed::from_double(16.7 / 0.068, 8),
                                      fixed::from_double(1.0 / 0.22, 8),
                                      fixed::from_double((0.097 / 0.068 - 1.0) * 100.0, 8)};

bool hotend_model_valid(const HotendModel& model);

class Feedforward {
 public:
  constexpr Feedforward() = default;

  // Precondition: hotend_model_valid(model). ~2 × 40,000 AVR cycles (set-up code).
  void configure(const HotendModel& model);

  // The feedforward duty (duty_q16) for this target and part-fan duty (0..255); 0 at or
  // below the ambient. ~200 AVR cycles.
  uint16_t duty_q16(int32_t target_q8, uint8_t fan_duty) const;

 private:
  fixed::Multiplier per_rise_q8_{0, 0};  // duty_q16 per temp_q8 of rise: 65535 / A_q8
  uint32_t fan_per_unit_q24_ = 0;        // F/100/255 per fan unit, Q24 (≤ 328,965)
};

}  // namespace control
