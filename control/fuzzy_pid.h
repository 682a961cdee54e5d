// Fuzzy-PID (seed 002): a PID (control/pid.h, reused as is) whose gains a fuzzy supervisor
// retunes every control period from the error e and its rate of change ec:
//   kp = kp0 + s_p·Δkp,  ki = ki0 + s_i·Δki,  kd = kd0 + s_d·Δkd,  Δ on the universe 0…3
// with Δ read from the fixed-point surfaces of fuzzy_surface.h (Mamdani max–min, centroid).
//
// Inputs to the supervisor (seed 002's quantization, units ours):
//   e  = target − measured, °C;       universe e_u  = clamp(e_factor · e, −3, 3)
//   ec = de/dt = −d(measured)/dt, °C/s (per second so the factor does not depend on the control
//        period; from the measurement so a new target does not kick it; low-pass filtered over
//        ~4 periods against ADC noise); universe ec_u = clamp(ec_factor · ec, −3, 3)
// Defaults 0.4 /°C and 0.6 s/°C as in seed 002: |e| ≥ 7.5 °C and |ec| ≥ 5 °C/s saturate.
#pragma once

#include <stdint.h>

#include "control/controller.h"
#include "control/fuzzy_surface.h"
#include "control/pid.h"

namespace control {

struct FuzzyPidConfig {
  PidGains base;             // kp0, ki0, kd0: the gains at Δ = 0 (M301 units, Q16)
  PidGains scale;            // s_p, s_i, s_d: gain added per unit of Δ (M301 units, Q16)
  uint16_t e_factor_q12;     // universe units per °C of error, Q12 (0.4 → 1638)
  uint16_t ec_factor_q12;    // universe units per °C/s of error change, Q12 (0.6 → 2458)
};

constexpr uint16_t kSeedEFactorQ12 = 1638;   // 0.4 /°C (seed 002)
constexpr uint16_t kSeedEcFactorQ12 = 2458;  // 0.6 s/°C (seed 002)

// Seed 002's literal setting: scale factors 1 in gain units. With M301-unit hotend gains
// (Kp ≈ 20, Ki ≈ 1, Kd ≈ 100) this moves kp and kd by a few percent and ki by up to 3×, so it
// is offered for comparison, not as the default.
constexpr FuzzyPidConfig fuzzy_seed002_config(const PidGains& base) {
  return FuzzyPidConfig{base, PidGains{65536, 65536, 65536}, kSeedEFactorQ12, kSeedEcFactorQ12};
}

// The default: the supervisor scales the user's own (M301-tuned) gains. Δ = 1.5, the middle of
// the output universe, gives exactly `nominal`; Δ = 0…3 spans nominal·(1 ∓ spread_pct/100).
// (Centroid defuzzification keeps Δ within 1/6…17/6, so the extremes are never quite reached.)
namespace detail {
// x·num/den for x ≥ 0 without overflowing int32 (x may be near 2^30): split x = q·den + r.
__attribute__((noinline)) constexpr int32_t mul_frac(int32_t x, uint8_t num, uint8_t den) { return x / den * num + x % den * num / den; }
constexpr PidGains mul_frac(const PidGains& g, uint8_t num, uint8_t den) {
  return PidGains{mul_frac(g.kp_q16, num, den), mul_frac(g.ki_q16, num, den), mul_frac(g.kd_q16, num, den)};
}
}  // namespace detail

constexpr FuzzyPidConfig fuzzy_config_around(const PidGains& nominal, uint8_t spread_pct) {
  return FuzzyPidConfig{PidGains{nominal.kp_q16 - detail::mul_frac(nominal.kp_q16, spread_pct, 100),
                                 nominal.ki_q16 - detail::mul_frac(nominal.ki_q16, spread_pct, 100),
                                 nominal.kd_q16 - detail::mul_frac(nominal.kd_q16, spread_pct, 100)},
                        detail::mul_frac(nominal, spread_pct, 150), kSeedEFactorQ12, kSeedEcFactorQ12};
}
constexpr uint8_t kDefaultFuzzySpreadPct = 50;

class FuzzyPid final : public Controller {
 public:
  // `load` reads the surface grid (fuzzy::make_default_surfaces()): from PROGMEM in the
  // firmware, from an array on the host.
  explicit constexpr FuzzyPid(fuzzy::LoadCell load) : load_(load) {}

  // True if every gain the schedule can reach (base + 3·scale) is valid for Pid, e_factor is at
  // least 0.024 /°C, ec_factor per control period fits the fixed point (period ≥ ~40 ms at 0.6),
  // and each scale coefficient times Δ (≤ 3) fits the 32-bit per-step arithmetic.
  static bool valid(const FuzzyPidConfig& config, uint16_t period_ms);

  // Precondition: valid(). Keeps the PID's integrator (bumpless while hot). Set-up code: the
  // long divisions of the PID coefficients of base, scale and base + 3·scale happen here, so
  // that step() combines them with multiplies only (coefficients are linear in the gains).
  void configure(const FuzzyPidConfig& config, uint16_t period_ms);

  uint16_t step(const StepInput& in) override;
  void reset() override;
  void init_bumpless(int32_t measured_q8, uint16_t duty_q16) override;
  void set_feedforward(uint16_t duty_q16) { pid_.set_feedforward(duty_q16); }
  void preset_integral(uint16_t duty_q16) { pid_.preset_integral(duty_q16); }
  // The PID the schedule drives (its feedforward and integrator are the fuzzy-PID's).
  Pid& pid() { return pid_; }

  const FuzzyPidConfig& config() const { return config_; }
  // The supervisor runs over four step() calls (inputs, surfaces, kp/ki, kd and apply); the
  // PID steps every call. Its latest outputs and the gains they schedule:
  fuzzy::Deltas last_deltas() const { return deltas_; }
  PidGains last_gains() const;
  // The PID coefficients of those deltas (what configuring last_gains() would give).
  PidCoefficients last_coefficients() const;
  // The supervisor's latest inputs, universe × 256.
  int16_t last_e_u_q8() const { return e_u_q8_; }
  int16_t last_ec_u_q8() const { return ec_u_q8_; }

 private:
  static constexpr uint8_t kEcFilterShift = 2;  // ec low-pass: α = 1/4 per period (τ ≈ 3.5 periods)
  static constexpr uint8_t kEcFrac = 4;         // extra fraction bits of the filtered change

  // The step's scalars first, the PID (86 bytes) last: AVR's LDD/STD reach offsets 0..63 only.
  fuzzy::LoadCell load_;
  int32_t e_limit_q8_ = 0;           // error clamp just past universe saturation, temp_q8
  uint16_t ec_gain_q12_ = 0;         // universe per (temp_q8 change per period) × 256, Q12
  int16_t change_q12_ = 0;           // filtered measurement change per period, °C × 2^12
  int32_t previous_q8_ = 0;          // last measurement, temp_q8
  bool have_previous_ = false;
  uint8_t phase_ = 0;                // supervisor work of this step: 0 inputs, 1 surfaces,
                                     // 2 kp and ki, 3 kd and apply (step() comments why)
  int16_t e_u_q8_ = 0;
  int16_t ec_u_q8_ = 0;
  fuzzy::Deltas deltas_{0, 0, 0};
  FuzzyPidConfig config_{{0, 0, 0}, {0, 0, 0}, kSeedEFactorQ12, kSeedEcFactorQ12};
  PidCoefficients base_c_{{0, 0}, {0, 0}, {0, 0}};   // Pid::coefficients(config_.base)
  PidCoefficients scale_c_{{0, 0}, {0, 0}, {0, 0}};  // Pid::coefficients(config_.scale)
  PidCoefficients pending_{{0, 0}, {0, 0}, {0, 0}};  // the schedule being computed
  Pid pid_;
};

}  // namespace control
