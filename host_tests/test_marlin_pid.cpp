// The Marlin-style baseline (control/marlin_pid.h): band switching, integral limit, filtered
// derivative, bumpless take-over, feedforward — and in closed loop on hotend40w against a
// double-precision implementation of the same structure.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "control/marlin_pid.h"
#include "host_tests/hotend40w_model.h"

namespace {

using control::MarlinPid;
using control::PidGains;
using test_plant::to_q8;

constexpr uint16_t kPeriodMs = 128;
constexpr int32_t kQ8 = 256;

PidGains gains(double kp, double ki, double kd) {
  return {int32_t(std::lround(kp * 65536)), int32_t(std::lround(ki * 65536)), int32_t(std::lround(kd * 65536))};
}

MarlinPid configured(double kp, double ki, double kd) {
  MarlinPid pid;
  pid.configure(gains(kp, ki, kd), kPeriodMs);
  return pid;
}

// The structure in double, output 0..1: band ±10 °C, I within 0..1, D low-passed with K1 0.95.
class ReferenceMarlin {
 public:
  ReferenceMarlin(double kp, double ki, double kd) : kp_(kp / 255), ki_(ki / 255), kd_(kd / 255) {}
  double step(double target_c, double measured_c) {
    const double e = target_c - measured_c;
    const double change = have_previous_ ? measured_c - previous_c_ : 0.0;
    previous_c_ = measured_c;
    have_previous_ = true;
    if (std::fabs(e) > 10.0) {
      in_band_ = false;
      return e > 0 ? 1.0 : 0.0;
    }
    if (!in_band_) i_ = d_ = 0, in_band_ = true;
    d_ = 0.95 * d_ + 0.05 * (-kd_ * change / test_plant::kPeriodS);
    i_ = std::min(std::max(i_ + ki_ * test_plant::kPeriodS * e, 0.0), 1.0);
    return std::min(std::max(kp_ * e + i_ + d_, 0.0), 1.0);
  }

 private:
  double kp_, ki_, kd_, i_ = 0, d_ = 0, previous_c_ = 0;
  bool have_previous_ = false, in_band_ = false;
};

TEST(MarlinPid, FullOnOrOffOutsideTheFunctionalRange) {
  MarlinPid pid = configured(22.2, 1.08, 114);
  EXPECT_EQ(pid.step(210 * kQ8, 199 * kQ8), 65535);  // 11 °C below: full power
  EXPECT_FALSE(pid.in_band());
  EXPECT_EQ(pid.step(210 * kQ8, 221 * kQ8), 0);      // 11 °C above: off
  EXPECT_FALSE(pid.in_band());
  pid.step(210 * kQ8, 205 * kQ8);                     // 5 °C below: PID
  EXPECT_TRUE(pid.in_band());
}

TEST(MarlinPid, ProportionalTermInsideTheBandIsInMarlinUnits) {
  MarlinPid pid = configured(10, 0, 0);
  EXPECT_EQ(pid.step(210 * kQ8, 205 * kQ8), 50 * 257);  // Kp·e = 50 on the 0..255 scale
  EXPECT_EQ(pid.step(210 * kQ8, 210 * kQ8), 0);
}

TEST(MarlinPid, IntegralIsLimitedToFullPowerAndRestartsOnReentry) {
  MarlinPid pid = configured(0.5, 20, 0);
  for (int i = 0; i < 2000; ++i) pid.step(210 * kQ8, 201 * kQ8);  // 9 °C below for 256 s
  EXPECT_EQ(pid.integral_q16(), 65535);                           // not beyond 100 %
  for (int i = 0; i < 2000; ++i) pid.step(210 * kQ8, 219 * kQ8);
  EXPECT_EQ(pid.integral_q16(), 0);                               // nor below 0
  for (int i = 0; i < 50; ++i) pid.step(210 * kQ8, 205 * kQ8);
  EXPECT_GT(pid.integral_q16(), 0);
  pid.step(210 * kQ8, 190 * kQ8);  // leaves the band...
  pid.step(210 * kQ8, 205 * kQ8);  // ...and re-enters: one sample of integration since the restart
  EXPECT_NEAR(pid.integral_q16(), 20.0 * 0.128 * 5 * 257, 2);
}

TEST(MarlinPid, DerivativeIsFilteredWithK1) {
  // Kd = 12.8 s: a 1 °C rise in one 128 ms sample is D_raw = −100 on the 0..255 scale; K1 = 0.95
  // lets 5 % of it through at once, then 0.95 of that stays per quiet sample.
  MarlinPid pid = configured(0.01, 0, 12.8);
  pid.step(210 * kQ8, 205 * kQ8);
  const int first = pid.step(210 * kQ8, 206 * kQ8);  // P ≈ 0.04, D ≈ −5 → clamped 0
  EXPECT_EQ(first, 0);
  MarlinPid falling = configured(0.01, 0, 12.8);
  falling.step(210 * kQ8, 206 * kQ8);
  const double d1 = falling.step(210 * kQ8, 205 * kQ8) / 257.0;  // D = +5, P = 0.05
  EXPECT_NEAR(d1, 5.0 + 0.05, 0.02);
  const double d2 = falling.step(210 * kQ8, 205 * kQ8) / 257.0;
  EXPECT_NEAR(d2, 0.95 * 5.0 + 0.05, 0.02);
}

TEST(MarlinPid, TakesOverWithoutAJump) {
  // 2 °C below the target P alone is 44.4 (11,411 duty_q16): the integral covers the rest.
  for (uint16_t duty : {uint16_t{12000}, uint16_t{30000}, uint16_t{65535}}) {
    MarlinPid pid = configured(22.2, 1.08, 114);
    pid.init_bumpless(208 * kQ8, duty);
    EXPECT_NEAR(pid.step(210 * kQ8, 208 * kQ8), duty, 1) << duty;
  }
  MarlinPid at_target = configured(22.2, 1.08, 114);
  at_target.init_bumpless(210 * kQ8, 0);
  EXPECT_EQ(at_target.step(210 * kQ8, 210 * kQ8), 0);
  // Outside the band the structure is on/off whatever was handed over.
  MarlinPid far = configured(22.2, 1.08, 114);
  far.init_bumpless(150 * kQ8, 20000);
  EXPECT_EQ(far.step(210 * kQ8, 150 * kQ8), 65535);
}

TEST(MarlinPid, FeedforwardIsAddedInsideTheBandOnly) {
  MarlinPid pid = configured(10, 0, 0);
  pid.set_feedforward(20000);
  EXPECT_EQ(pid.step(210 * kQ8, 205 * kQ8), 50 * 257 + 20000);
  EXPECT_EQ(pid.step(210 * kQ8, 230 * kQ8), 0);
  EXPECT_EQ(pid.step(210 * kQ8, 150 * kQ8), 65535);
}

TEST(MarlinPidClosedLoop, MatchesTheDoubleStructureAndHoldsHotend40w) {
  const double kp = 22.2, ki = 1.08, kd = 114;  // Marlin's stock E3D-class gains
  MarlinPid pid = configured(kp, ki, kd);
  ReferenceMarlin ref(kp, ki, kd);
  test_plant::Hotend40w plant, ref_plant;
  double max_diff_c = 0, max_c = 0, sum_error = 0;
  int n_tail = 0;
  for (int k = 0; k < 6000; ++k) {  // 768 s
    const uint16_t duty = pid.step(210 * kQ8, to_q8(plant.sensor_c()));
    const double ref_duty = ref.step(210.0, ref_plant.sensor_c());
    plant.advance(duty / 65535.0);
    ref_plant.advance(ref_duty);
    max_diff_c = std::max(max_diff_c, std::fabs(plant.sensor_c() - ref_plant.sensor_c()));
    max_c = std::max(max_c, plant.sensor_c());
    if (k >= 4000) sum_error += 210.0 - plant.sensor_c(), ++n_tail;
  }
  EXPECT_LT(max_diff_c, 0.05);
  EXPECT_LT(max_c, 215.0);  // the baseline may overshoot, but not wildly
  EXPECT_LT(std::fabs(sum_error / n_tail), 0.05);
}

}  // namespace
