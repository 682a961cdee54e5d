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
  int32_t time_constant_q8;  // C: s × 256 (ModelReference's plant lag)
  int32_t dead_time_q8;      // D: s × 256 (ModelReference's delay, as a chain of lags)
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
// a == b, field by field (one copy for the bank's and the protection's change checks).
bool same_model(const HotendModel& a, const HotendModel& b);

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

// Model-following reference for PID + feedforward (2-degree-of-freedom): the heat-up the M307
// model promises, so that P and I act only on the deviation from it. Time-optimal for the model:
// full power (or off) until the model's undelayed state x reaches the target, then the steady
// duty, which holds x there; the reference is x delayed by the dead time D.
//   x += α·(25 °C + A·u − x),  α = 2h/(C + h)    u = 1 (heating) or 0 (cooling) until x crosses
//                                                the target, the crossing update's u landing x
//                                                on it (trapezoidal rule, every other period)
//   reference(t) = x(t − D)                      delay line: kTaps taps ≈ D/(kTaps − 1) apart,
//                                                linear interpolation between two taps; D
//                                                realised to a control period
// x in "q16" (°C × 65536), taps and reference temp_q8. α is mantissa_q16 / 2^16, or / 2^24 when
// α < 1/256, so that C = 600 s keeps 12 significant bits. The x update and the reference
// update alternate (one multiply-add pair per period: ~150 AVR cycles).
// Lead rule (lag-type fits, D ≥ C/8, heating): a FOPDT cannot respond before its dead
// time, so a reading that runs ahead of the reference shows lags the two-point fit folded into
// D, which store more heat than the fit predicts (seed003: 9–10 °C of overshoot, seed000-4 7 °C).
// Full power then ends ¾ × (lead − 1 °C) earlier (5/16 × for D ≥ 64 s), and x approaches the
// target on the steady duty with a 2·D time constant instead of landing on it
// (docs/controllers.md).
class ModelReference {
 public:
  static constexpr uint8_t kTaps = 16;  // a power of two (ring index by mask); 64 B of RAM
  struct Output {
    int32_t reference_q8;  // where the model says the hotend is now (°C × 256)
    uint16_t duty_q16;     // the feedforward duty for the next period
  };

  constexpr ModelReference() = default;

  // Precondition: hotend_model_valid(model), 10 ≤ period_ms ≤ 2000. Set-up code (long divisions).
  void configure(const HotendModel& model, uint16_t period_ms);
  // The model's output starts at rest at the measured temperature; its undelayed state x at
  // x_q8: the measurement for a heat-up from here, the target for a bumpless take-over (the
  // model then holds the steady duty instead of starting a full-power heat-up).
  void start(int32_t measured_q8, int32_t x_q8);
  // One control period: steady_q16 is Feedforward::duty_q16 for the target and fan; measured_q8
  // the hotend's reading (kNoReading: the model alone, no lead rule).
  static constexpr int32_t kNoReading = -0x7FFFFFFFL - 1;
  Output step(int32_t target_q8, uint16_t steady_q16, int32_t measured_q8 = kNoReading);
  // True once the model rests at the target, its delayed output included: the heat-up (or
  // cool-down) the model plans is over and the steady duty holds it there.
  bool holds(int32_t target_q8) const { return x_q16_ == target_q8 * 256 && reference_q8_ == target_q8; }

 private:
  struct Rate {
    uint16_t mantissa_q16;
    bool shift8;  // α = mantissa_q16 / 2^24 instead of / 2^16
  };
  static Rate rate(int32_t time_constant_q8, uint16_t period_ms);
  static int32_t scaled(int32_t difference_q16, const Rate& r);  // α·difference
  int32_t scaled(int32_t difference_q16) const { return scaled(difference_q16, plant_); }

  Rate plant_{0, false};
  Rate coast_{0, false};              // the lead rule's approach (configure)
  int32_t full_q16_ = 0;              // 25 °C + A: where 100 % duty drives x
  // duty_q16 per q16 of x's one-update step: 1/(α·A). The update in which x reaches the target
  // gets the duty that lands it there, not full power (or off) for the whole update: on a fast
  // hotend (seed002: 18 °C/s) two periods at full power are ~4 °C of overshoot.
  fixed::Multiplier per_step_q16_{0, 0};
  uint16_t spacing_ = 0;              // periods between taps, even (0: no dead time)
  uint8_t offset_taps_ = 0;           // (kTaps − 1)·spacing_ − D = offset_taps_·spacing_ + offset_
  uint16_t offset_ = 0;               // periods, 0..spacing_ − 1
  uint16_t frac_per_period_q16_ = 0;  // 1/spacing_, Q16
  int32_t x_q16_ = 0;
  int32_t tap_q8_[kTaps] = {};
  int32_t reference_q8_ = 0;
  uint16_t duty_q16_ = 0;             // the model's duty decided at the last x update
  uint16_t count_ = 0;                // periods since the newest tap
  uint8_t newest_ = 0;
  bool odd_ = false;
  bool landing_ = false;              // duty_q16_ is the update's landing duty, not full/off
  uint8_t lead_share_16ths_ = 12;     // the lead rule's share of the lead (configure)
  int16_t lead_min_q8_ = 0;           // leads up to this are a D error, not a lag (configure)
  // Lead rule (issue 7): the most the reading has run ahead of the model's output during this
  // heat-up, less kLeadSlackQ8. A FOPDT cannot respond before its dead time; a plant that does
  // stores heat in lags the two-point fit folded into D, and the full-power phase ends
  // ¾ (long D: 5/16) × lead earlier (docs/controllers.md). temp_q8, ≥ 0.
  int32_t lead_q8_ = 0;
};

}  // namespace control
