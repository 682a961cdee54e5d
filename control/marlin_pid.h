// Marlin's hotend PID structure, rebuilt from the facts its configuration documents (never its
// code) as the benchmark's baseline and as a user option (M310 S3):
// - PID_FUNCTIONAL_RANGE 10: more than 10 °C below the target the heater is fully on, more
//   than 10 °C above it is off, and the integral restarts from zero when the error comes back
//   inside the band ("bang-bang outside, PID inside");
// - inside: P + I + D with the integral term limited to 0..255 (Marlin's PID_MAX, 100 % duty:
//   the integral can never ask for less than nothing or more than everything);
// - D on the measurement, low-passed with PID_K1 = 0.95 per sample: D ← K1·D + (1 − K1)·D_raw.
// Gains are the same M301 values (Marlin units) the other PID-family controllers use; the
// per-sample coefficients come from control::Pid::coefficients() so both share the conversion.
// A model feedforward (set_feedforward) is simply added to the output inside the band.
#pragma once

#include <stdint.h>

#include "control/controller.h"
#include "control/fixed.h"
#include "control/pid.h"

namespace control {

class MarlinPid final : public Controller {
 public:
  static constexpr int32_t kFunctionalRangeQ8 = 10L * 256;  // PID_FUNCTIONAL_RANGE, °C × 256
  // 1 − PID_K1 in Q16: the share of the new raw derivative per sample (0.05 · 65536 = 3276.8).
  static constexpr uint16_t kDerivativeAlphaQ16 = 3277;

  constexpr MarlinPid() = default;

  // Precondition: Pid::valid(gains, period_ms). Keeps the integrator (M301 while hot: no bump
  // beyond the change of P and D).
  void configure(const PidGains& gains, uint16_t period_ms);

  uint16_t step(int32_t target_q8, int32_t measured_q8);  // returns duty_q16
  uint16_t step(const StepInput& in) override { return step(in.target_q8, in.measured_q8); }
  void reset() override;
  // Inside the band the next step's output equals duty_q16 (the integrator takes the
  // difference, within its 0..100 % limit). Outside the band the structure is on/off by design.
  void init_bumpless(int32_t measured_q8, uint16_t duty_q16) override;
  void set_feedforward(uint16_t duty_q16) { feedforward_q16_ = duty_q16; }

  // Introspection for tests: the integral term as duty_q16, and whether the last step was PID.
  uint16_t integral_q16() const { return static_cast<uint16_t>(fixed::shr_round(integrator_q32_, 16)); }
  bool in_band() const { return in_band_; }

 private:
  // Same internal units as control::Pid: outputs "q24" = duty_q16 × 2^8, integrator "q32".
  static constexpr int32_t kFullQ24 = 65535L << 8;
  static constexpr uint32_t kFullQ32 = 65535UL << 16;

  PidCoefficients c_{{0, 0}, {0, 0}, {0, 0}};
  int32_t i_error_limit_q8_ = 0;    // |e| for I: |increment| ≤ 2^29 q32 (as in Pid)
  int32_t d_change_limit_q8_ = 0;   // |Δmeasured| for D: |raw D| ≤ 2^29 q24
  uint32_t integrator_q32_ = 0;     // I, 0..kFullQ32 (Marlin's integral limit 0..PID_MAX)
  int32_t derivative_q24_ = 0;      // filtered D
  int32_t previous_q8_ = 0;         // last measurement
  int32_t bumpless_q24_ = 0;        // output to continue from at the next in-band step
  uint16_t feedforward_q16_ = 0;
  bool have_previous_ = false;
  bool in_band_ = false;            // the last step ran the PID (not full on/off)
  bool bumpless_pending_ = false;
};

}  // namespace control
