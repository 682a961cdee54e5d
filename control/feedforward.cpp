#include "control/feedforward.h"

namespace control {
namespace {

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

}  // namespace control
