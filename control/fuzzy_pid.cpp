#include "control/fuzzy_pid.h"

#include "control/fixed.h"

namespace control {

constexpr uint8_t FuzzyPid::kEcFilterShift;
constexpr uint8_t FuzzyPid::kEcFrac;

namespace {

// Largest scale factor whose base + 3·scale could still be a valid gain (checked before the sum
// so that it cannot overflow int32).
constexpr int32_t kMaxScaleQ16 = Pid::kMaxKdQ16 / 3;

// Smallest e factor (Q12) for which the clamped error fits the fast quantization below.
constexpr uint16_t kMinEFactorQ12 = 100;  // 0.024 /°C: the universe would span ±125 °C

// scale_q16 · Δ_q8 / 256 with AVR's widening multiplies (fixed::mul_q16): Δ_q8 ≤ 768, so
// Δ_q8·64 is a Q16 fraction below 1; the last 2 bits are lost (≤ 4/65536 of a gain unit).
int32_t scaled_gain_q16(int32_t scale_q16, uint16_t delta_q8) {
  return fixed::mul_q16(scale_q16, static_cast<uint16_t>(delta_q8 << 6)) * 4;
}

// The largest gains the schedule reaches (Δ = 3): base + 3·scale. noinline: valid() and
// configure() each had the three sums inlined.
__attribute__((noinline)) PidGains top_gains(const FuzzyPidConfig& c) {
  return PidGains{c.base.kp_q16 + 3 * c.scale.kp_q16, c.base.ki_q16 + 3 * c.scale.ki_q16,
                  c.base.kd_q16 + 3 * c.scale.kd_q16};
}

// ec per measurement change per period: ec_factor · 1000 / period_ms (Q12), or 0 if too large.
uint32_t ec_gain_q12(uint16_t ec_factor_q12, uint16_t period_ms) {
  return period_ms == 0 ? 0 : (uint32_t{ec_factor_q12} * 1000u + period_ms / 2) / period_ms;
}

// Scale coefficients up to this whole part keep whole · Δ_q8 (Δ_q8 ≤ 768) inside uint32.
constexpr uint32_t kMaxScaleWhole = 0xFFFFFFFFUL / 768;

// The middle of the output universe (Δ = 1.5, × 256): the nominal gains of fuzzy_config_around.
constexpr uint16_t kMidDeltaQ8 = 384;

// out = base + scale·Δ_q8/256, the scheduled coefficient, with multiplies only. In Q16 units:
// scale·Δ/256 = whole·Δ·2^8 + frac·Δ/2^8; the low byte of whole·Δ becomes fraction bits.
// frac·Δ is rounded (≤ ½ of 2^-16): the scheduled gain is exact to the coefficient's LSB.
// Then, as Pid::coefficients() does (fixed::without_small_fraction), a coefficient ≥ 1024 is
// rounded to a whole number, so that the PID's multiply by it is one multiply, not three.
// Inlined and written into place: as calls returning structs the three cost ~250 cycles more.
__attribute__((always_inline)) inline void schedule(const fixed::Multiplier& base, const fixed::Multiplier& scale,
                                                    uint16_t delta_q8, fixed::Multiplier& out) {
  const uint32_t whole_delta = scale.whole * delta_q8;
  const uint32_t frac_q16 = uint32_t{base.frac_q16} + ((whole_delta & 0xFF) << 8) +
                            ((fixed::mul_u16(scale.frac_q16, delta_q8) + 128) >> 8);  // < 3·2^16
  const uint32_t whole = base.whole + (whole_delta >> 8) + (frac_q16 >> 16);
  if (whole < 1024) {
    out.whole = whole;
    out.frac_q16 = static_cast<uint16_t>(frac_q16);
  } else {
    out.whole = whole + ((frac_q16 >> 15) & 1);
    out.frac_q16 = 0;
  }
}

// noinline: valid() checks three pairs (12 B of AVR flash as calls).
__attribute__((noinline)) bool scale_ok(int32_t base_q16, int32_t scale_q16) {
  return base_q16 >= 0 && base_q16 <= Pid::kMaxKdQ16 && scale_q16 >= 0 && scale_q16 <= kMaxScaleQ16;
}

int16_t clamp_universe(int32_t u_q8) {
  return static_cast<int16_t>(fixed::clamp<int32_t>(u_q8, -fuzzy::kUniverseMaxQ8, fuzzy::kUniverseMaxQ8));
}

}  // namespace

bool FuzzyPid::valid(const FuzzyPidConfig& c, uint16_t period_ms) {
  if (!scale_ok(c.base.kp_q16, c.scale.kp_q16) || !scale_ok(c.base.ki_q16, c.scale.ki_q16) ||
      !scale_ok(c.base.kd_q16, c.scale.kd_q16))
    return false;
  const PidGains top = top_gains(c);
  const uint32_t ec_gain = ec_gain_q12(c.ec_factor_q12, period_ms);
  if (!Pid::valid(top, period_ms) || c.e_factor_q12 < kMinEFactorQ12 || ec_gain == 0 || ec_gain > 0xFFFF) return false;
  const PidCoefficients s = Pid::coefficients(c.scale, period_ms);
  return s.kp.whole <= kMaxScaleWhole && s.ki.whole <= kMaxScaleWhole && s.kd.whole <= kMaxScaleWhole;
}

void FuzzyPid::configure(const FuzzyPidConfig& config, uint16_t period_ms) {
  config_ = config;
  ec_gain_q12_ = static_cast<uint16_t>(ec_gain_q12(config.ec_factor_q12, period_ms));
  // |e| beyond which e_u saturates (+1): ≤ 768·4096/100 + 1 = 31458 for valid factors.
  e_limit_q8_ = static_cast<int32_t>((uint32_t{fuzzy::kUniverseMaxQ8} << 12) / config.e_factor_q12 + 1);
  // The PID's overflow clamps are computed for the largest gains the schedule reaches;
  // step() then sets the scheduled coefficients (capped there) before each use.
  pid_.configure(top_gains(config), period_ms);
  base_c_ = Pid::coefficients(config.base, period_ms);
  scale_c_ = Pid::coefficients(config.scale, period_ms);
  // Until the supervisor has run: the nominal gains (the middle of the schedule, Δ = 1.5).
  // Through Pid::coefficients() rather than the per-step schedule(): set-up code, and it keeps
  // three inlined copies of schedule() out of the image.
  deltas_ = fuzzy::Deltas{kMidDeltaQ8, kMidDeltaQ8, kMidDeltaQ8};
  pid_.set_coefficients(Pid::coefficients(last_gains(), period_ms));
  phase_ = 0;
}

void FuzzyPid::reset() {
  pid_.reset();
  have_previous_ = false;
  change_q12_ = 0;
  phase_ = 0;
}

void FuzzyPid::init_bumpless(int32_t measured_q8, uint16_t duty_q16) {
  pid_.init_bumpless(measured_q8, duty_q16);
  previous_q8_ = measured_q8;
  have_previous_ = true;
  change_q12_ = 0;
  phase_ = 0;
}

uint16_t FuzzyPid::step(const StepInput& in) {
  // ec: measurement change per period, low-passed in Q12 (°C × 4096); ec = −dT/dt. Every
  // period, so the filter's time constant does not depend on the supervisor's phases.
  if (!have_previous_) {
    previous_q8_ = in.measured_q8;
    have_previous_ = true;
  }
  const int32_t change_q8 = fixed::clamp<int32_t>(in.measured_q8 - previous_q8_, -2047, 2047);
  previous_q8_ = in.measured_q8;
  change_q12_ = static_cast<int16_t>(
      change_q12_ + fixed::shr_round(change_q8 * (1 << kEcFrac) - change_q12_, kEcFilterShift));

  // The supervisor's work is spread over four periods, so that no step exceeds the 3,000-cycle
  // budget (together ~1,700 AVR cycles; interpolation alone ~550): the gains follow e and ec
  // with a lag of 3 to 6 periods (0.4–0.8 s), small against a hotend's time constants (≥ 20 s)
  // and dead times (5–20 s). The PID itself steps every period.
  switch (phase_) {
    case 0: {
      // e: °C × 256 → universe × 256. The error is first clamped to just past where the universe
      // saturates, so that e·factor >> 8 fits 16 bits: the Q12 → Q8 shift is then a free byte
      // move plus a 4-bit shift on 16 bits (avr-gcc loops over 32-bit shifts by 12).
      const int32_t error_q8 = fixed::clamp(in.target_q8 - in.measured_q8, -e_limit_q8_, e_limit_q8_);
      const int16_t e_u_q12 =
          static_cast<int16_t>(fixed::mul_i16_u16(static_cast<int16_t>(error_q8), config_.e_factor_q12) >> 8);
      e_u_q8_ = clamp_universe((e_u_q12 + 8) >> 4);
      ec_u_q8_ = clamp_universe(-fixed::shr_round(fixed::mul_i16_u16(change_q12_, ec_gain_q12_), 16));
      break;
    }
    case 1:
      deltas_ = fuzzy::interpolate<fuzzy::kSurfaceStepShift>(load_, e_u_q8_, ec_u_q8_);
      break;
    default: {
      // Phase 2: kp and ki; phase 3: kd, then apply. One inlined schedule() in a loop over the
      // three coefficients (a copy per coefficient cost ~500 B of AVR flash).
      const fixed::Multiplier* base[3] = {&base_c_.kp, &base_c_.ki, &base_c_.kd};
      const fixed::Multiplier* scale[3] = {&scale_c_.kp, &scale_c_.ki, &scale_c_.kd};
      const uint16_t delta_q8[3] = {deltas_.dkp_q8, deltas_.dki_q8, deltas_.dkd_q8};
      fixed::Multiplier* out[3] = {&pending_.kp, &pending_.ki, &pending_.kd};
      const uint8_t last = phase_ == 2 ? 2 : 3;
      for (uint8_t i = phase_ == 2 ? 0 : 2; i < last; ++i) schedule(*base[i], *scale[i], delta_q8[i], *out[i]);
      if (last == 3) pid_.set_coefficients(pending_);
      break;
    }
  }
  phase_ = static_cast<uint8_t>((phase_ + 1) & 3);
  return pid_.step(in.target_q8, in.measured_q8);
}

PidGains FuzzyPid::last_gains() const {
  return PidGains{config_.base.kp_q16 + scaled_gain_q16(config_.scale.kp_q16, deltas_.dkp_q8),
                  config_.base.ki_q16 + scaled_gain_q16(config_.scale.ki_q16, deltas_.dki_q8),
                  config_.base.kd_q16 + scaled_gain_q16(config_.scale.kd_q16, deltas_.dkd_q8)};
}

PidCoefficients FuzzyPid::last_coefficients() const {
  PidCoefficients c;
  schedule(base_c_.kp, scale_c_.kp, deltas_.dkp_q8, c.kp);
  schedule(base_c_.ki, scale_c_.ki, deltas_.dki_q8, c.ki);
  schedule(base_c_.kd, scale_c_.kd, deltas_.dkd_q8, c.kd);
  return c;
}

}  // namespace control
