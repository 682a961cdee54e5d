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

// ec per measurement change per period: ec_factor · 1000 / period_ms (Q12), or 0 if too large.
uint32_t ec_gain_q12(uint16_t ec_factor_q12, uint16_t period_ms) {
  return period_ms == 0 ? 0 : (uint32_t{ec_factor_q12} * 1000u + period_ms / 2) / period_ms;
}

bool scale_ok(int32_t base_q16, int32_t scale_q16) {
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
  const PidGains top{c.base.kp_q16 + 3 * c.scale.kp_q16, c.base.ki_q16 + 3 * c.scale.ki_q16,
                     c.base.kd_q16 + 3 * c.scale.kd_q16};
  const uint32_t ec_gain = ec_gain_q12(c.ec_factor_q12, period_ms);
  return Pid::valid(top, period_ms) && c.e_factor_q12 >= kMinEFactorQ12 && ec_gain > 0 && ec_gain <= 0xFFFF;
}

void FuzzyPid::configure(const FuzzyPidConfig& config, uint16_t period_ms) {
  config_ = config;
  period_ms_ = period_ms;
  ec_gain_q12_ = static_cast<uint16_t>(ec_gain_q12(config.ec_factor_q12, period_ms));
  // |e| beyond which e_u saturates (+1): ≤ 768·4096/100 + 1 = 31458 for valid factors.
  e_limit_q8_ = static_cast<int32_t>((uint32_t{fuzzy::kUniverseMaxQ8} << 12) / config.e_factor_q12 + 1);
  pid_.configure(config.base, period_ms);  // step() sets the scheduled gains before each use
}

void FuzzyPid::reset() {
  pid_.reset();
  have_previous_ = false;
  change_q12_ = 0;
}

void FuzzyPid::init_bumpless(int32_t measured_q8, uint16_t duty_q16) {
  pid_.init_bumpless(measured_q8, duty_q16);
  previous_q8_ = measured_q8;
  have_previous_ = true;
  change_q12_ = 0;
}

uint16_t FuzzyPid::step(const StepInput& in) {
  // e: °C × 256 → universe × 256. The error is first clamped to just past where the universe
  // saturates, so that e·factor >> 8 fits 16 bits: the Q12 → Q8 shift is then a free byte move
  // plus a 4-bit shift on 16 bits (avr-gcc loops over 32-bit shifts by 12).
  const int32_t error_q8 = fixed::clamp(in.target_q8 - in.measured_q8, -e_limit_q8_, e_limit_q8_);
  const int16_t e_u_q12 = static_cast<int16_t>(fixed::mul_i16_u16(static_cast<int16_t>(error_q8), config_.e_factor_q12) >> 8);
  e_u_q8_ = clamp_universe((e_u_q12 + 8) >> 4);

  // ec: measurement change per period, low-passed in Q12 (°C × 4096); ec = −dT/dt.
  if (!have_previous_) {
    previous_q8_ = in.measured_q8;
    have_previous_ = true;
  }
  const int32_t change_q8 = fixed::clamp<int32_t>(in.measured_q8 - previous_q8_, -2047, 2047);
  previous_q8_ = in.measured_q8;
  change_q12_ = static_cast<int16_t>(
      change_q12_ + fixed::shr_round(change_q8 * (1 << kEcFrac) - change_q12_, kEcFilterShift));
  ec_u_q8_ = clamp_universe(-fixed::shr_round(fixed::mul_i16_u16(change_q12_, ec_gain_q12_), 16));

  deltas_ = fuzzy::interpolate<fuzzy::kSurfaceStepShift>(load_, e_u_q8_, ec_u_q8_);
  // TODO(pid owner): Pid::configure() is set-up code (~41,000 AVR cycles of long division);
  // a per-step coefficient setter (docs/fuzzy_pid.md, "What the PID needs") would bring this
  // step to ~2,800 cycles. Until then the schedule is exact but slow (~2.7 ms per 128 ms).
  pid_.configure(last_gains(), period_ms_);
  return pid_.step(in.target_q8, in.measured_q8);
}

PidGains FuzzyPid::last_gains() const {
  return PidGains{config_.base.kp_q16 + scaled_gain_q16(config_.scale.kp_q16, deltas_.dkp_q8),
                  config_.base.ki_q16 + scaled_gain_q16(config_.scale.ki_q16, deltas_.dki_q8),
                  config_.base.kd_q16 + scaled_gain_q16(config_.scale.kd_q16, deltas_.dkd_q8)};
}

}  // namespace control
