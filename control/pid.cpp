#include "control/pid.h"

namespace control {

// C++14 needs namespace-scope definitions for static constexpr members that get odr-used.
constexpr uint16_t Pid::kDefaultDerivativeFilterMs;
constexpr int32_t Pid::kMaxKpQ16;
constexpr int32_t Pid::kMaxKiQ16;
constexpr int32_t Pid::kMaxKdQ16;
constexpr uint16_t Pid::kMinPeriodMs;
constexpr uint16_t Pid::kMaxPeriodMs;
constexpr int32_t Pid::kFullQ24;
constexpr uint32_t Pid::kFullQ32;

namespace {

// Per-sample coefficients. One output unit (0–255 scale) is 65535·2^8/255 = 257·2^8 q24, and
// 1 °C is 2^8 temp_q8, so a gain G per °C is G·257 q24 per temp_q8. Each is gain_q16·b/c:
fixed::Multiplier kp_multiplier(int32_t kp_q16) {  // Kp·257
  return fixed::multiplier_ratio(static_cast<uint32_t>(kp_q16), 257, 65536);
}
fixed::Multiplier ki_multiplier(int32_t ki_q16, uint16_t period_ms) {  // Ki·(ms/1000)·257·2^8 (q32)
  // 257·256/1000 = 8224/125
  return fixed::multiplier_ratio(static_cast<uint32_t>(ki_q16), uint32_t{period_ms} * 8224, 125UL << 16);
}
fixed::Multiplier kd_multiplier(int32_t kd_q16, uint16_t period_ms) {  // Kd/(ms/1000)·257
  return fixed::multiplier_ratio(static_cast<uint32_t>(kd_q16), 257000, uint32_t{period_ms} << 16);
}

// A nonzero gain must keep a coefficient ≥ ½: otherwise one temp_q8 step (1/256 °C) would move
// its term by less than the rounding of the term (P, D) or of the integrator increment (I).
bool representable(int32_t gain_q16, fixed::Multiplier m) {
  return gain_q16 == 0 || m.whole > 0 || m.frac_q16 >= 0x8000;
}

// The three multipliers before without_small_fraction. noinline: valid() and coefficients()
// each had the three conversions inlined.
__attribute__((noinline)) PidCoefficients exact_coefficients(const PidGains& g, uint16_t period_ms) {
  return PidCoefficients{kp_multiplier(g.kp_q16), ki_multiplier(g.ki_q16, period_ms), kd_multiplier(g.kd_q16, period_ms)};
}

// Largest |x| with |x|·(m.whole + 1) ≤ bound (the precondition of fixed::mul_round).
__attribute__((noinline)) int32_t input_limit(uint32_t bound, fixed::Multiplier m) {
  return static_cast<int32_t>(bound / (m.whole + 1));
}

}  // namespace

bool Pid::valid(const PidGains& g, uint16_t period_ms) {
  if (period_ms < kMinPeriodMs || period_ms > kMaxPeriodMs) return false;
  if (g.kp_q16 < 0 || g.ki_q16 < 0 || g.kd_q16 < 0) return false;
  if (g.kp_q16 > kMaxKpQ16 || g.ki_q16 > kMaxKiQ16 || g.kd_q16 > kMaxKdQ16) return false;
  const PidCoefficients m = exact_coefficients(g, period_ms);
  return representable(g.kp_q16, m.kp) && representable(g.ki_q16, m.ki) && representable(g.kd_q16, m.kd);
}

PidCoefficients Pid::coefficients(const PidGains& gains, uint16_t period_ms) {
  const PidCoefficients m = exact_coefficients(gains, period_ms);
  return PidCoefficients{fixed::without_small_fraction(m.kp), fixed::without_small_fraction(m.ki),
                         fixed::without_small_fraction(m.kd)};
}

// noinline: LTO inlined it into configure() and the fuzzy step (with input_limit: 132 B of AVR
// flash as calls, for a few cycles when the fuzzy step switches gains).
__attribute__((noinline)) void Pid::set_coefficients(const PidCoefficients& c) {
  // A smaller whole part only widens the margin of the clamps (|x|·(whole + 1) ≤ bound).
  c_.kp = c.kp.whole > kp_ceiling_ ? fixed::Multiplier{kp_ceiling_, 0} : c.kp;
  c_.ki = c.ki.whole > ki_ceiling_ ? fixed::Multiplier{ki_ceiling_, 0} : c.ki;
  c_.kd = c.kd.whole > kd_ceiling_ ? fixed::Multiplier{kd_ceiling_, 0} : c.kd;
}

void Pid::configure(const PidGains& gains, uint16_t period_ms, uint16_t derivative_filter_ms) {
  gains_ = gains;
  period_ms_ = period_ms;
  c_ = coefficients(gains, period_ms);
  kp_ceiling_ = c_.kp.whole;
  ki_ceiling_ = c_.ki.whole;
  kd_ceiling_ = c_.kd.whole;
  p_error_limit_q8_ = input_limit(1UL << 30, c_.kp);
  i_error_limit_q8_ = input_limit(1UL << 29, c_.ki);
  d_change_limit_q8_ = input_limit(1UL << 29, c_.kd);
  const uint32_t alpha = fixed::mul_div_u32(65536, period_ms, uint32_t{derivative_filter_ms} + period_ms);
  alpha_q16_ = alpha > 0xFFFF ? 0xFFFF : static_cast<uint16_t>(alpha);  // Tf = 0: α = 1 − 2^-16
}

void Pid::set_feedforward(uint16_t duty_q16) {
  // I + F moves with F; where that leaves 0..100 % the clamp takes it from I (anti-windup).
  const bool down = duty_q16 < feedforward_q16_;
  const uint16_t change_q16 = down ? feedforward_q16_ - duty_q16 : duty_q16 - feedforward_q16_;
  move_integrator(static_cast<uint32_t>(change_q16) << 16, down);
  feedforward_q16_ = duty_q16;
}

void Pid::move_integrator(uint32_t magnitude_q32, bool down) {  // magnitude ≤ kFullQ32
  if (down) {
    integrator_q32_ = integrator_q32_ > magnitude_q32 ? integrator_q32_ - magnitude_q32 : 0;
  } else {
    const uint32_t room_q32 = kFullQ32 - integrator_q32_;
    integrator_q32_ = magnitude_q32 < room_q32 ? integrator_q32_ + magnitude_q32 : kFullQ32;
  }
}

void Pid::reset() {
  integrator_q32_ = static_cast<uint32_t>(feedforward_q16_) << 16;  // I = 0
  derivative_q24_ = 0;
  have_previous_ = false;
  bumpless_pending_ = false;
}

void Pid::init_bumpless(int32_t measured_q8, uint16_t duty_q16) {
  previous_q8_ = measured_q8;
  have_previous_ = true;
  derivative_q24_ = 0;
  bumpless_q24_ = static_cast<int32_t>(duty_q16) << 8;
  bumpless_pending_ = true;
}

uint16_t Pid::step(int32_t target_q8, int32_t measured_q8) {
  // Magnitudes (q24; full power ≈ 2^24): |P| ≤ 2^30, |D| ≤ 2^29, I + F within 0..2^24, so every
  // sum below stays inside int32.
  const int32_t error_q8 = target_q8 - measured_q8;
  const int32_t p_q24 = fixed::mul_round(fixed::clamp(error_q8, -p_error_limit_q8_, p_error_limit_q8_), c_.kp);

  if (!have_previous_) {
    previous_q8_ = measured_q8;
    have_previous_ = true;
  }
  if (c_.kd.whole != 0 || c_.kd.frac_q16 != 0) {
    const int32_t change_q8 =
        fixed::clamp(measured_q8 - previous_q8_, -d_change_limit_q8_, d_change_limit_q8_);
    derivative_q24_ += fixed::mul_q16(-fixed::mul_round(change_q8, c_.kd) - derivative_q24_, alpha_q16_);
  } else {
    derivative_q24_ = 0;  // PI (Kd 0, e.g. SIMC on a dead-time plant): skip two multiplies
  }
  previous_q8_ = measured_q8;

  const int32_t pd_q24 = p_q24 + derivative_q24_;
  if (bumpless_pending_) {
    const int32_t i_q24 = fixed::clamp(bumpless_q24_ - pd_q24, int32_t{0}, kFullQ24);
    integrator_q32_ = static_cast<uint32_t>(i_q24) << 8;
    bumpless_pending_ = false;
  }

  // Conditional integration: skip an increment that would drive a saturated output further.
  const int32_t increment_q32 =
      fixed::mul_round(fixed::clamp(error_q8, -i_error_limit_q8_, i_error_limit_q8_), c_.ki);
  const int32_t before_q24 = pd_q24 + static_cast<int32_t>(integrator_q32_ >> 8);
  if (increment_q32 > 0 && before_q24 < kFullQ24) {
    move_integrator(static_cast<uint32_t>(increment_q32), false);
  } else if (increment_q32 < 0 && before_q24 > 0) {
    move_integrator(static_cast<uint32_t>(-increment_q32), true);
  }

  const int32_t out_q24 = pd_q24 + static_cast<int32_t>(fixed::shr_round(integrator_q32_, 8));
  return static_cast<uint16_t>(fixed::shr_round(fixed::clamp(out_q24, int32_t{0}, kFullQ24), 8));
}

}  // namespace control
