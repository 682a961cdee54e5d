#include "control/marlin_pid.h"

namespace control {

// C++14 needs namespace-scope definitions for static constexpr members that get odr-used.
constexpr int32_t MarlinPid::kFunctionalRangeQ8;
constexpr uint16_t MarlinPid::kDerivativeAlphaQ16;
constexpr int32_t MarlinPid::kFullQ24;
constexpr uint32_t MarlinPid::kFullQ32;

void MarlinPid::configure(const PidGains& gains, uint16_t period_ms) {
  c_ = Pid::coefficients(gains, period_ms);
  // Largest inputs whose products stay inside int32 (fixed::mul_round: |x|·(whole + 1) ≤ 2^30).
  // P needs none: inside the band |e| ≤ 2560 and Kp·257 ≤ 257,000 (Pid::valid) keep it < 2^30.
  i_error_limit_q8_ = static_cast<int32_t>((1UL << 29) / (c_.ki.whole + 1));
  d_change_limit_q8_ = static_cast<int32_t>((1UL << 29) / (c_.kd.whole + 1));
}

void MarlinPid::reset() {
  integrator_q32_ = 0;
  derivative_q24_ = 0;
  have_previous_ = false;
  in_band_ = false;
  bumpless_pending_ = false;
}

void MarlinPid::init_bumpless(int32_t measured_q8, uint16_t duty_q16) {
  previous_q8_ = measured_q8;
  have_previous_ = true;
  derivative_q24_ = 0;
  in_band_ = true;  // so a first in-band step keeps the handed-over integral instead of zeroing it
  bumpless_q24_ = static_cast<int32_t>(duty_q16) << 8;
  bumpless_pending_ = true;
}

uint16_t MarlinPid::step(int32_t target_q8, int32_t measured_q8) {
  const int32_t error_q8 = target_q8 - measured_q8;
  if (!have_previous_) previous_q8_ = measured_q8;
  const int32_t change_q8 = fixed::clamp(measured_q8 - previous_q8_, -d_change_limit_q8_, d_change_limit_q8_);
  previous_q8_ = measured_q8;
  have_previous_ = true;

  if (error_q8 > kFunctionalRangeQ8 || error_q8 < -kFunctionalRangeQ8) {
    in_band_ = false;
    bumpless_pending_ = false;  // on/off rules here; a hand-over cannot be honoured
    return error_q8 > 0 ? 0xFFFF : 0;
  }
  if (!in_band_) {  // (re-)entering the band: Marlin restarts the integral and the derivative
    integrator_q32_ = 0;
    derivative_q24_ = 0;
    in_band_ = true;
  }

  const int32_t p_q24 = fixed::mul_round(error_q8, c_.kp);
  // D ← D + (1 − K1)·(D_raw − D); |D_raw|, |D| ≤ 2^29 so the difference fits int32.
  derivative_q24_ += fixed::mul_q16(-fixed::mul_round(change_q8, c_.kd) - derivative_q24_, kDerivativeAlphaQ16);

  // I += Ki·h·e, kept within 0..100 % (the integral-term limit).
  const int32_t increment_q32 =
      fixed::mul_round(fixed::clamp(error_q8, -i_error_limit_q8_, i_error_limit_q8_), c_.ki);
  if (increment_q32 >= 0) {
    const uint32_t room_q32 = kFullQ32 - integrator_q32_;
    integrator_q32_ += static_cast<uint32_t>(increment_q32) < room_q32 ? static_cast<uint32_t>(increment_q32) : room_q32;
  } else {
    const uint32_t down_q32 = static_cast<uint32_t>(-increment_q32);
    integrator_q32_ = integrator_q32_ > down_q32 ? integrator_q32_ - down_q32 : 0;
  }

  const int32_t others_q24 = p_q24 + derivative_q24_ + (static_cast<int32_t>(feedforward_q16_) << 8);
  if (bumpless_pending_) {  // the integral takes whatever makes this output the handed-over duty
    const int32_t i_q24 = fixed::clamp(bumpless_q24_ - others_q24, int32_t{0}, kFullQ24);
    integrator_q32_ = static_cast<uint32_t>(i_q24) << 8;
    bumpless_pending_ = false;
  }
  const int32_t out_q24 = others_q24 + static_cast<int32_t>(fixed::shr_round(integrator_q32_, 8));
  return static_cast<uint16_t>(fixed::shr_round(fixed::clamp(out_q24, int32_t{0}, kFullQ24), 8));
}

}  // namespace control
