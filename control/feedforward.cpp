#include "control/feedforward.h"

#include <string.h>

namespace control {
namespace {

// The lead rule ignores this much of the reading's lead over the model (noise, quantisation,
// a small mismatch of an exact FOPDT's fit).
constexpr int32_t kLeadSlackQ8 = 1L * 256;
// From this D on, full power ends 5/16 of the lead early instead of ¾: on seed000-4 (D 163 s,
// 35 °C of lead at t = D) ¾ ended it at 0.77 of the model's time and left the steady window
// 0.7 °C low with 2.2 °C p-p; 1/4…7/16 pass HIL3 there, 5/16 by the widest margin (host rig,
// seed_loop.h). seed003 (D 9.9 s) needs the ¾: 5/16 overshot 2.2–3.3 °C.
constexpr int32_t kLeadLongDeadTimeQ8 = 64L * 256;
// x coasting on the steady duty rests on the target from this close (°C × 65536).
constexpr int32_t kLeadSnapQ16 = 1L << 16;

// Largest rise the feedforward looks at: beyond 300 °C above ambient the target is refused
// anyway (275 °C maximum), and this keeps rise · (whole + 1) within fixed::mul_round's 2^30.
constexpr int32_t kMaxRiseQ8 = 300L * 256;

}  // namespace

bool hotend_model_valid(const HotendModel& m) {
  return m.rise_q8 >= kModelMinRiseQ8 && m.rise_q8 <= kModelMaxRiseQ8 &&
         m.time_constant_q8 >= kModelMinTimeConstantQ8 && m.time_constant_q8 <= kModelMaxTimeConstantQ8 &&
         m.dead_time_q8 >= 0 && m.dead_time_q8 <= kModelMaxDeadTimeQ8 && m.fan_loss_pct_q8 >= 0 &&
         m.fan_loss_pct_q8 <= kModelMaxFanLossPctQ8;
}

// Four int32 fields and no padding, so bytewise equality is fieldwise equality; memcmp is a
// smaller loop on AVR than four 32-bit compares.
static_assert(sizeof(HotendModel) == 4 * sizeof(int32_t), "HotendModel: four int32 fields, no padding");
bool same_model(const HotendModel& a, const HotendModel& b) { return memcmp(&a, &b, sizeof(HotendModel)) == 0; }

void Feedforward::configure(const HotendModel& m) {
  // 65535 / A_q8 ≤ 25.6 for A ≥ 10 °C: whole ≤ 25, so 76,800 · 26 < 2^30.
  per_rise_q8_ = fixed::multiplier_ratio(65535, 1, static_cast<uint32_t>(m.rise_q8));
  // F_q8 / 256 / 100 / 255 · 2^24 = F_q8 · 2^16 / 25,500.
  fan_per_unit_q24_ = fixed::mul_div_u32(static_cast<uint32_t>(m.fan_loss_pct_q8), 65536, 25500);
}

uint16_t Feedforward::duty_q16(int32_t target_q8, uint8_t fan_duty) const {
  const int32_t rise_q8 = fixed::clamp(target_q8 - kFeedforwardAmbientQ8, int32_t{0}, kMaxRiseQ8);
  const int32_t base_q16 = fixed::clamp(fixed::mul_round(rise_q8, per_rise_q8_), int32_t{0}, int32_t{65535});
  // × (1 + fan·F/25,500): the extra part is base · fan · fan_per_unit / 2^24, done as
  // base · (fan·fan_per_unit / 2^8) / 2^16 so that no product needs more than 32 bits
  // (fan · fan_per_unit ≤ 255 · 328,965 < 2^27).
  const uint32_t extra_q16 = (static_cast<uint32_t>(fan_duty) * fan_per_unit_q24_ + 128) >> 8;  // ≤ 5·2^16
  const int32_t extra = fixed::mul_round(base_q16, fixed::Multiplier{extra_q16 >> 16, static_cast<uint16_t>(extra_q16)});
  return fixed::sat_u16(base_q16 + extra);
}

constexpr uint8_t ModelReference::kTaps;

ModelReference::Rate ModelReference::rate(int32_t time_constant_q8, uint16_t period_ms) {
  // x advances every other period, so its step is 2h. α = 2h/(C + h) = (ms·512) / (C_q8·1000 +
  // ms·256): the trapezoidal rule, 1 − e^(−2h/C) to within (2h/C)³/12 (backward Euler's
  // 2h/(C + 2h) is slow by (2h/C)²/2: seed002's model reached 210 °C ~0.7 °C late, and the
  // heat-up overshot by that). den < 2^30 for C ≤ 3600 s.
  const uint32_t num = uint32_t{period_ms} * 512;
  const uint32_t den = static_cast<uint32_t>(time_constant_q8) * 1000 + num / 2;
  // α < 1/256: keep it × 256 (a byte shift per step) so that it holds ≥ 8 significant bits
  // (C = 3600 s: α·2^24 ≈ 1,200); else plain Q16.
  const bool small = (num << 8) < den;
  const uint32_t m = fixed::mul_div_u32(num, small ? (1UL << 24) : (1UL << 16), den);
  return Rate{static_cast<uint16_t>(m > 0xFFFF ? 0xFFFF : m), small};
}

void ModelReference::configure(const HotendModel& m, uint16_t period_ms) {
  plant_ = rate(m.time_constant_q8, period_ms);
  // The lead rule's approach after full power: x moves to the target on the steady duty with
  // 2·D (on a lag-type plant the heat still stored is in the lags the fit folded into D; on
  // seed003 D alone left 1.9–2.0 °C of overshoot, C 0.5–1.0 °C and a slow end, and a C-based
  // time slowed hotend40w's heat-up, whose C is its block's 245 s), at least 1 s (rate() needs
  // a time constant ≥ h). Off (mantissa 0) for D < C/8: a lag that short stores little beyond
  // the model's heat (hotend40w, D/C 0.02: the rule only made its heat-up 13 % slower; seed003's
  // and seed000-4's fits have D/C 0.28, seed000-5's 0.11).
  const int32_t d = m.dead_time_q8;
  coast_ = 8 * d >= m.time_constant_q8 ? rate(2 * d > 256 ? 2 * d : 256, period_ms) : Rate{0, false};
  lead_share_16ths_ = d >= kLeadLongDeadTimeQ8 ? 5 : 12;
  // The lead a FOPDT hotend shows when its identified D is 1/8 too long (the model's initial
  // slope A/C times D/8) is no lag: below it the rule keeps out. A D 4 % long on fopdt-120-25
  // (3.7 °C of lead) ended full power early and settled in 1.70 × bound instead of 1.00
  // (simavr); the lags it is for lead by 34–37 °C (seed003, seed000-4) against 8–16 °C here.
  // A·D/(8C) ≤ 2^19·2^18/2^11 < 2^32, 8C < 2^23 (mul_div_u32's bounds), clamped to int16.
  const uint32_t lead_min = fixed::mul_div_u32(static_cast<uint32_t>(m.rise_q8), static_cast<uint32_t>(d),
                                               8 * static_cast<uint32_t>(m.time_constant_q8));
  lead_min_q8_ = static_cast<int16_t>(lead_min > 32767 ? 32767 : lead_min);
  full_q16_ = (kFeedforwardAmbientQ8 + m.rise_q8) << 8;
  // α·A in q16: rise_q8·256 < 2^28, so scaled() holds it; ≥ 1 for every valid model
  // (α ≥ 2^-24·mantissa, A ≥ 10 °C).
  const int32_t step_q16 = scaled(m.rise_q8 << 8);
  per_step_q16_ = fixed::multiplier_ratio(65535, 1, static_cast<uint32_t>(step_q16 > 0 ? step_q16 : 1));
  // Taps every spacing_ periods (even: they are written at reference updates, every other
  // period), (kTaps − 1)·spacing_ ≥ D; the reference reads offset_ periods later than the
  // oldest tap so that the delay is D to the period. D ≤ 600 s at h ≥ 10 ms: ≤ 60,000 periods.
  const uint32_t dead_periods =
      (fixed::mul_div_u32(static_cast<uint32_t>(m.dead_time_q8), 1000, period_ms) + 128) >> 8;
  const uint32_t per_tap = (dead_periods + 2 * (kTaps - 1) - 1) / (2 * (kTaps - 1));  // ceil, in updates
  spacing_ = static_cast<uint16_t>(2 * per_tap);
  // (kTaps − 1)·spacing_ − D < 2·(kTaps − 1) periods: whole taps (≤ 14, so the pair read stays
  // inside the ring) and the rest.
  const uint32_t slack = uint32_t{spacing_} * (kTaps - 1) - dead_periods;
  offset_taps_ = spacing_ > 0 ? static_cast<uint8_t>(slack / spacing_) : 0;
  offset_ = spacing_ > 0 ? static_cast<uint16_t>(slack % spacing_) : 0;
  frac_per_period_q16_ = spacing_ > 1 ? static_cast<uint16_t>(65536UL / spacing_) : 0;
}

void ModelReference::start(int32_t measured_q8, int32_t x_q8) {
  x_q16_ = x_q8 << 8;
  for (int32_t& t : tap_q8_) t = measured_q8;
  reference_q8_ = measured_q8;
  duty_q16_ = 0;
  landing_ = false;
  lead_q8_ = 0;
  newest_ = 0;
  count_ = 0;
  odd_ = false;
}

ModelReference::Output ModelReference::step(int32_t target_q8, uint16_t steady_q16, int32_t measured_q8) {
  // Half the work each period (the x update, then the reference), so no step pays for both.
  odd_ = !odd_;
  if (odd_) {
    const int32_t target_q16 = target_q8 << 8;
    int32_t x = x_q16_;
    uint16_t duty_q16 = steady_q16;
    landing_ = false;
    // The lead rule, heating only: while x is below the target, the reading's lead over the
    // model's output (|difference| < 2^20 for readings and model within ±2048 °C).
    if (measured_q8 != kNoReading && x < target_q16 && coast_.mantissa_q16 != 0) {
      const int32_t lead_q8 = measured_q8 - reference_q8_ - kLeadSlackQ8;
      if (lead_q8 > lead_q8_) lead_q8_ = lead_q8;
    }
    // ¾ of the lead, or 5/16 for a long D, q16: lead_q8 < 2^20 (|difference| above), so < 2^28.
    const int32_t early_q16 = lead_q8_ > lead_min_q8_ ? lead_q8_ * lead_share_16ths_ * 16 : 0;
    // The update is linear in the duty u: Δx(u) = Δx(0) + u·α·A. Heating at full power (or
    // cooling with the heater off) until x would pass the target; that update lands x on it with
    // u = (target − x − Δx(0)) / (α·A), from the full-power step less the overshoot it would
    // make: 0 ≤ overshoot ≤ α·|25 °C + A − x| (≤ α·A unless x is outside 25 °C … 25 °C + A), and
    // with x within ±2048 °C overshoot × per_step < 2^16 · 2^12 < 2^30 (mul_round).
    if (x < target_q16) {
      const int32_t step = scaled(full_q16_ - x);
      if (x + step + early_q16 < target_q16) {
        x += step;
        duty_q16 = 65535;
      } else if (x + step < target_q16) {
        // The lead rule ended full power: x approaches on the steady duty (25 °C + A·u_ss is
        // the target), and rests on it from within kLeadSnapQ16.
        x += scaled(target_q16 - x, coast_);
        if (target_q16 - x < kLeadSnapQ16) x = target_q16;
      } else {
        duty_q16 = fixed::sat_u16(65535 - fixed::mul_round(x + step - target_q16, per_step_q16_));
        x = target_q16;
        landing_ = true;
      }
    } else if (x > target_q16) {
      const int32_t step = scaled((kFeedforwardAmbientQ8 << 8) - x);
      if (x + step > target_q16) {
        x += step;
        duty_q16 = 0;
      } else {
        duty_q16 = fixed::sat_u16(fixed::mul_round(target_q16 - (x + step), per_step_q16_));
        x = target_q16;
        landing_ = true;
      }
    }
    x_q16_ = x;
    duty_q16_ = duty_q16;
  } else if (spacing_ == 0) {
    reference_q8_ = (x_q16_ + 128) >> 8;  // no dead time
  } else {
    // Delay line: a tap every spacing_ periods; the reference interpolates between the two
    // oldest, (kTaps − 1)·spacing_ periods ≈ D behind x.
    count_ = static_cast<uint16_t>(count_ + 2);
    if (count_ >= spacing_) {
      count_ = 0;
      newest_ = static_cast<uint8_t>((newest_ + 1) & (kTaps - 1));
      tap_q8_[newest_] = (x_q16_ + 128) >> 8;
    }
    uint16_t position = static_cast<uint16_t>(count_ + offset_);  // periods past the oldest tap
    uint8_t older = static_cast<uint8_t>(newest_ + 1 + offset_taps_);
    if (position >= spacing_) {
      position = static_cast<uint16_t>(position - spacing_);
      ++older;
    }
    const int32_t a_q8 = tap_q8_[older & (kTaps - 1)];
    const int32_t b_q8 = tap_q8_[(older + 1) & (kTaps - 1)];
    const uint16_t frac_q16 = static_cast<uint16_t>(position * frac_per_period_q16_);
    reference_q8_ = a_q8 + fixed::mul_q16_round(b_q8 - a_q8, frac_q16);
  }
  // The steady duty follows the fan at once; only the heat-up phases come from the model.
  const uint16_t duty_q16 = landing_ || duty_q16_ == 65535 || duty_q16_ == 0 ? duty_q16_ : steady_q16;
  return Output{reference_q8_, duty_q16};
}

int32_t ModelReference::scaled(int32_t difference_q16, const Rate& r) {
  // |difference| < 2^28 here (temperatures within ±2048 °C).
  const int32_t s = fixed::mul_q16_round(difference_q16, r.mantissa_q16);
  return r.shift8 ? (s + 128) >> 8 : s;
}

}  // namespace control
