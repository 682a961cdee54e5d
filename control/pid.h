// Discrete PID for the hotend heater, integer-only (runs on AVR every control period).
// Structure (positional form, sample period h):
//   u = P + I + D + F, clamped to 0..100 %
//   P = Kp·e                        e = target − measured
//   I += Ki·h·e                     conditional integration: frozen while u is saturated and e
//                                   would push it further; I + F kept within 0..100 %
//   D ← D + α·(−Kd·Δmeasured/h − D) derivative of the measurement (no kick on setpoint steps),
//                                   first-order low-pass, α = h/(Tf + h) (backward Euler)
//   F                               feedforward duty (set_feedforward), e.g. from a plant model
// Gains are in Marlin's M301 units: output on a 0–255 scale, Kp per °C, Ki per °C·s, Kd in s.
#pragma once

#include <stdint.h>

#include "control/controller.h"
#include "control/fixed.h"

namespace control {

// Gains as hosts type them (M301 P I D), in Q16: kp_q16 = Kp·65536 and so on.
struct PidGains {
  int32_t kp_q16;  // output units (0–255 scale) per °C
  int32_t ki_q16;  // output units per °C per second
  int32_t kd_q16;  // output units per °C/s
};

// The per-sample multipliers configure() derives from gains and period (internal units below).
struct PidCoefficients {
  fixed::Multiplier kp;  // q24 per temp_q8 of error: Kp·257
  fixed::Multiplier ki;  // q32 per temp_q8 of error per sample: Ki·h·257·256
  fixed::Multiplier kd;  // q24 per temp_q8 of measurement change per sample: Kd/h·257
};

class Pid final : public Controller {
 public:
  // Derivative low-pass time constant Tf unless configure() is told otherwise: Td/N with N ≈ 5
  // for typical hotend gains (Td = Kd/Kp ≈ 5 s); Åström & Hägglund, "Advanced PID Control"
  // (ISA 2006) §3.3, give N = 2…20. Long enough to keep 1/256 °C steps of a noisy reading from
  // rattling the heater, short against hotend time constants of 20–40 s.
  static constexpr uint16_t kDefaultDerivativeFilterMs = 1000;

  // What valid() accepts. Upper limits are far beyond useful hotend gains (Kp = 1000 is full
  // power at ¼ °C of error) and keep every intermediate inside int32.
  static constexpr int32_t kMaxKpQ16 = 1000L << 16;
  static constexpr int32_t kMaxKiQ16 = 100L << 16;
  static constexpr int32_t kMaxKdQ16 = 10000L << 16;
  static constexpr uint16_t kMinPeriodMs = 10;
  static constexpr uint16_t kMaxPeriodMs = 2000;

  constexpr Pid() = default;

  // True if gains and period are within the limits above and no nonzero gain is so small that
  // its per-sample coefficient rounds away (see pid.cpp). The firmware refuses M301 otherwise.
  static bool valid(const PidGains& gains, uint16_t period_ms);

  // Sets gains and period (precondition: valid()). Keeps the integrator, which is stored in
  // output units, so that changing gains while hot does not make the output jump. Set-up code:
  // about 40,000 AVR cycles of long division.
  void configure(const PidGains& gains, uint16_t period_ms,
                 uint16_t derivative_filter_ms = kDefaultDerivativeFilterMs);

  // For gain scheduling (fuzzy-PID, issue 3): the coefficients of some gains, computed at set-up
  // time, and a per-step setter with no division. Each coefficient is capped at the one
  // configure() set, for which the overflow clamps were computed — so configure() with the
  // largest gains the schedule reaches. gains() keeps reporting configure()'s gains.
  static PidCoefficients coefficients(const PidGains& gains, uint16_t period_ms);
  void set_coefficients(const PidCoefficients& c);

  // One control period: returns the heater duty for the next period (duty_q16, 65535 = 100 %).
  // target_q8, measured_q8: °C × 256, each within ±2^24 (±65536 °C).
  uint16_t step(int32_t target_q8, int32_t measured_q8);
  uint16_t step(const StepInput& in) override { return step(in.target_q8, in.measured_q8); }

  // Forgets integrator, derivative and the previous measurement (gains and feedforward stay).
  void reset() override;

  // Take over from another controller: the next step() sets its integrator so that its output
  // (before that step's own integration) equals duty_q16 — no jump at the switch. Exact while
  // the I + F needed lies within its anti-windup range 0..100 %; beyond that (large error and
  // large Kp) the output saturates as the PID's own would.
  void init_bumpless(int32_t measured_q8, uint16_t duty_q16) override;

  // Feedforward duty added to the output (issue 3: model or part-fan feedforward). Anti-windup
  // keeps I + F within 0..100 %, so F + I never winds past the actuator.
  void set_feedforward(uint16_t duty_q16);

  // I := duty_q16 (on top of the feedforward, within 0..100 %): a heat-up can start from the
  // steady duty a model predicts instead of building it from the error (fuzzy-PID, whose rules
  // shrink ki far from the target).
  void preset_integral(uint16_t duty_q16) {
    integrator_q32_ = static_cast<uint32_t>(feedforward_q16_) << 16;
    move_integrator(static_cast<uint32_t>(duty_q16) << 16, false);
  }

  PidGains gains() const { return gains_; }
  uint16_t period_ms() const { return period_ms_; }

 private:
  // Output units inside: "q24" = duty_q16 × 2^8, so 100 % = 65535·2^8. The integrator holds I + F
  // as an unsigned fraction of full power with 8 more bits ("q32", 100 % = 65535·2^16): then the
  // anti-windup range is simply 0..100 %, F needs no work per sample, and q32 → q24 is a byte
  // shift. The 8 extra bits keep tiny increments (small Ki) from rounding away.
  static constexpr int32_t kFullQ24 = 65535L << 8;
  static constexpr uint32_t kFullQ32 = 65535UL << 16;

  void move_integrator(uint32_t magnitude_q32, bool down);  // ± within 0..100 % (anti-windup)

  uint16_t period_ms_ = 0;
  uint16_t alpha_q16_ = 0;               // derivative low-pass α = h/(Tf + h), Q16
  PidCoefficients c_{{0, 0}, {0, 0}, {0, 0}};  // in use
  // Input clamps that keep products in int32; each binds only where its term is already far
  // beyond full power (P: 64×, raw D: 32×) or one sample's increment exceeds ⅛ of full power.
  int32_t p_error_limit_q8_ = 0;         // |e| for P: |P| ≤ 2^30 q24
  int32_t i_error_limit_q8_ = 0;         // |e| for I: |increment| ≤ 2^29 q32
  int32_t d_change_limit_q8_ = 0;        // |Δmeasured| for D: |raw D| ≤ 2^29 q24
  uint32_t integrator_q32_ = 0;          // I + F, 0..kFullQ32
  int32_t derivative_q24_ = 0;           // filtered D
  uint16_t feedforward_q16_ = 0;         // F as duty_q16
  int32_t previous_q8_ = 0;              // last measurement, temp_q8
  int32_t bumpless_q24_ = 0;             // output to continue from at the next step
  bool have_previous_ = false;           // false until the first step after reset(): no D from it
  bool bumpless_pending_ = false;
  // Set-up values last: the step's members above sit within AVR's LDD/STD reach (offset <= 63).
  PidGains gains_{0, 0, 0};
  uint32_t kp_ceiling_ = 0;              // whole parts configure() set: set_coefficients' caps
  uint32_t ki_ceiling_ = 0;
  uint32_t kd_ceiling_ = 0;
};

}  // namespace control
