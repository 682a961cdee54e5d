// The fixed-point PID's individual properties, sample by sample (closed loop: test_pid_closed_loop).
#include <gtest/gtest.h>

#include <cmath>

#include "control/pid.h"

namespace {

using control::Pid;
using control::PidGains;

constexpr uint16_t kPeriodMs = 128;
constexpr int32_t kQ8 = 256;  // 1 °C in temp_q8

PidGains gains(double kp, double ki, double kd) {
  return {int32_t(std::lround(kp * 65536)), int32_t(std::lround(ki * 65536)),
          int32_t(std::lround(kd * 65536))};
}

Pid configured(double kp, double ki, double kd, uint16_t filter_ms = Pid::kDefaultDerivativeFilterMs) {
  Pid pid;
  pid.configure(gains(kp, ki, kd), kPeriodMs, filter_ms);
  return pid;
}

TEST(Pid, GainsRoundTripBitForBit) {
  Pid pid;
  const PidGains g{1454899, 70779, 7471104};  // 22.2, 1.08, 114 as M301 would parse them
  pid.configure(g, kPeriodMs);
  EXPECT_EQ(pid.gains().kp_q16, g.kp_q16);
  EXPECT_EQ(pid.gains().ki_q16, g.ki_q16);
  EXPECT_EQ(pid.gains().kd_q16, g.kd_q16);
  EXPECT_EQ(pid.period_ms(), kPeriodMs);
}

TEST(Pid, ValidAcceptsUsefulGainsAndRejectsTheRest) {
  EXPECT_TRUE(Pid::valid(gains(22.2, 1.08, 114), kPeriodMs));     // Marlin's stock hotend gains
  EXPECT_TRUE(Pid::valid(gains(0.33, 0.0137, 2), kPeriodMs));     // slow FOPDT plant
  EXPECT_TRUE(Pid::valid(gains(30.43, 3.27, 70.83), kPeriodMs));  // seed 003's autotune result
  EXPECT_TRUE(Pid::valid(gains(0, 0, 0), kPeriodMs));             // all off is representable
  EXPECT_TRUE(Pid::valid(gains(1000, 100, 10000), kPeriodMs));    // the limits themselves
  EXPECT_TRUE(Pid::valid(gains(1000, 100, 10000), Pid::kMinPeriodMs));
  EXPECT_TRUE(Pid::valid(gains(1000, 100, 10000), Pid::kMaxPeriodMs));

  EXPECT_FALSE(Pid::valid(gains(-1, 1, 1), kPeriodMs));
  EXPECT_FALSE(Pid::valid(gains(1, -1, 1), kPeriodMs));
  EXPECT_FALSE(Pid::valid(gains(1, 1, -1), kPeriodMs));
  EXPECT_FALSE(Pid::valid(gains(1000.01, 1, 1), kPeriodMs));
  EXPECT_FALSE(Pid::valid(gains(1, 100.01, 1), kPeriodMs));
  EXPECT_FALSE(Pid::valid(gains(1, 1, 10000.01), kPeriodMs));
  EXPECT_FALSE(Pid::valid(gains(22, 1, 100), 0));
  EXPECT_FALSE(Pid::valid(gains(22, 1, 100), Pid::kMinPeriodMs - 1));
  EXPECT_FALSE(Pid::valid(gains(22, 1, 100), Pid::kMaxPeriodMs + 1));
  // Too small to survive rounding: coefficient < ½ per 1/256 °C (per sample).
  EXPECT_FALSE(Pid::valid(gains(22, 0.00005, 100), kPeriodMs));  // Ki·h·257·256 = 0.42
  EXPECT_TRUE(Pid::valid(gains(22, 0.00007, 100), kPeriodMs));   // 0.59
  EXPECT_FALSE(Pid::valid(gains(22, 1, 0.0002), kPeriodMs));     // Kd/h·257 = 0.40
  EXPECT_TRUE(Pid::valid(gains(22, 1, 0.0003), kPeriodMs));      // 0.60
  EXPECT_FALSE(Pid::valid({1, 0, 0}, kPeriodMs));                // Kp = 2^-16: Kp·257 = 0.004
}

TEST(Pid, ProportionalTermIsInMarlinUnits) {
  // Kp = 10: 10 °C of error is 100 on the 0–255 scale = 100·257 in duty_q16.
  Pid pid = configured(10, 0, 0);
  EXPECT_EQ(pid.step(210 * kQ8, 200 * kQ8), 100 * 257);
  EXPECT_EQ(pid.step(210 * kQ8, 209 * kQ8), 10 * 257);
  EXPECT_EQ(pid.step(210 * kQ8, 210 * kQ8), 0);
  // Small gains keep 16 fraction bits: 0.33·257 = 84.81 q24 per 1/256 °C.
  Pid small = configured(0.33, 0, 0);
  EXPECT_NEAR(small.step(210 * kQ8, 10 * kQ8), 0.33 * 200 * 257, 0.5 + 0.33 * 200 * 257 * 1e-5);
  // Large ones (Kp·257 ≥ 1024) are rounded to whole q24 steps: ≤ 2^-11 relative.
  Pid large = configured(22.2, 0, 0);
  EXPECT_NEAR(large.step(210 * kQ8, 200 * kQ8), 222 * 257.0, 0.5 + 222 * 257.0 / 2048);
}

TEST(Pid, OutputIsClampedToZeroAndFullPower) {
  Pid pid = configured(50, 2, 100);
  EXPECT_EQ(pid.step(250 * kQ8, 20 * kQ8), 65535);  // huge positive error
  EXPECT_EQ(pid.step(20 * kQ8, 250 * kQ8), 0);      // huge negative error (and rising fast)
  pid.set_feedforward(65535);
  EXPECT_EQ(pid.step(250 * kQ8, 20 * kQ8), 65535);
  Pid extreme = configured(1000, 100, 10000);
  for (int32_t m : {-40 * kQ8, 0, 210 * kQ8, 400 * kQ8, 65535 * kQ8}) {
    const uint16_t a = extreme.step(300 * kQ8, m);
    const uint16_t b = extreme.step(-300 * kQ8, m);
    EXPECT_EQ(a, m < 300 * kQ8 ? 65535 : a);  // no wrap-around at extreme inputs
    EXPECT_EQ(b, 0);
  }
}

TEST(Pid, SetpointStepGivesNoDerivativeKick) {
  // Measurement constant: a 20 °C setpoint step may move only P (and I by one increment).
  Pid pid = configured(10, 0, 200);
  EXPECT_EQ(pid.step(100 * kQ8, 100 * kQ8), 0);
  EXPECT_EQ(pid.step(120 * kQ8, 100 * kQ8), 200 * 257);  // P alone: 10·20 = 200/255
  // A derivative-on-error controller would add Kd·20/h = 31250 on the 0–255 scale here.
}

TEST(Pid, DerivativeIsLowPassFilteredWithTheDocumentedTimeConstant) {
  // Kd only, measurement falling 1 °C/s: the unfiltered D is Kd·1 = 100 (of 255). The filtered
  // D approaches it as 1 − (1 − α)^n with α = h/(Tf + h).
  const double kd = 100, tf_s = 1.0, h = kPeriodMs / 1000.0, alpha = h / (tf_s + h);
  Pid pid = configured(0, 0, kd, 1000);
  double measured = 200 * kQ8;
  pid.step(0, int32_t(measured));
  for (int n = 1; n <= 40; ++n) {
    measured -= kQ8 * h;
    const double expected = kd * 257 * (1 - std::pow(1 - alpha, n));
    EXPECT_NEAR(pid.step(0, int32_t(std::lround(measured))), expected, 0.01 * kd * 257) << n;
  }
  // After ~Tf (8 samples of 128 ms) it has covered 1 − 1/e of the way, not all of it.
  Pid again = configured(0, 0, kd, 1000);
  again.step(0, 200 * kQ8);
  uint16_t out = 0;
  for (int n = 1; n <= 8; ++n) out = again.step(0, 200 * kQ8 - n * int32_t(kQ8 * h));
  EXPECT_GT(out, 0.55 * kd * 257);
  EXPECT_LT(out, 0.70 * kd * 257);
}

TEST(Pid, IntegratorDoesNotWindUpWhileSaturated) {
  Pid pid = configured(5, 1, 0);
  for (int n = 0; n < 2000; ++n) ASSERT_EQ(pid.step(200 * kQ8, 100 * kQ8), 65535);  // 256 s at 100 %
  // Error reverses slightly: a wound-up integrator would hold 100 % for minutes; this one has
  // not grown while saturated, so the output drops at once.
  EXPECT_LT(pid.step(200 * kQ8, 201 * kQ8), 65535 / 2);
}

TEST(Pid, AntiWindupAccountsForFeedforward) {
  Pid pid = configured(2, 1, 0);
  pid.set_feedforward(uint16_t(0.6 * 65535));
  for (int n = 0; n < 2000; ++n) pid.step(200 * kQ8, 199 * kQ8);  // I climbs ~0.05 % per sample
  EXPECT_EQ(pid.step(200 * kQ8, 199 * kQ8), 65535);
  // At zero error the output is F + I ≤ 100 %, and a small negative error leaves saturation.
  EXPECT_LE(pid.step(200 * kQ8, 200 * kQ8), 65535);
  EXPECT_LT(pid.step(200 * kQ8, 200 * kQ8 + 64), 65535);
  // Negative side: I never drives F + I below 0 %, so output comes back as soon as e > 0.
  for (int n = 0; n < 500; ++n) pid.step(100 * kQ8, 200 * kQ8);
  EXPECT_GT(pid.step(200 * kQ8, 200 * kQ8 - 64), 0);
}

TEST(Pid, FeedforwardAddsToTheOutput) {
  Pid pid = configured(10, 0, 0);
  pid.set_feedforward(20000);
  EXPECT_EQ(pid.step(210 * kQ8, 210 * kQ8), 20000);
  EXPECT_EQ(pid.step(210 * kQ8, 209 * kQ8), 20000 + 10 * 257);
}

TEST(Pid, BumplessTakeoverContinuesFromTheGivenDuty) {
  Pid pid = configured(22.2, 1.08, 114);
  pid.init_bumpless(208 * kQ8, 30000);
  // 2 °C below target: a cold start would output P (17 %); the takeover continues from 30000
  // (46 %) and moves by one integrator increment per sample, Ki·h·e = 1.08·0.128·2·257 duty_q16.
  const double increment = 1.08 * 0.128 * 2 * 257;
  const uint16_t first = pid.step(210 * kQ8, 208 * kQ8);
  EXPECT_NEAR(first, 30000 + increment, 1);
  EXPECT_NEAR(pid.step(210 * kQ8, 208 * kQ8), first + increment, 1);
  Pid cold = configured(22.2, 1.08, 114);
  EXPECT_NEAR(cold.step(210 * kQ8, 208 * kQ8), 22.2 * 2 * 257 + increment, 1);  // the bump avoided
}

TEST(Pid, BumplessTakeoverIsLimitedByTheIntegratorRange) {
  // 20 °C below target P alone is 174 %: no integrator within [0, 100 %] can bring the sum
  // down to 46 %, so the output saturates — as any PID with these gains would there.
  Pid pid = configured(22.2, 1.08, 114);
  pid.init_bumpless(190 * kQ8, 30000);
  EXPECT_EQ(pid.step(210 * kQ8, 190 * kQ8), 65535);
}

TEST(Pid, ResetForgetsHistoryButNotGains) {
  Pid pid = configured(5, 1, 50);
  for (int n = 0; n < 100; ++n) pid.step(200 * kQ8, (150 + n / 4) * kQ8);
  pid.reset();
  Pid fresh = configured(5, 1, 50);
  for (int n = 0; n < 10; ++n)
    EXPECT_EQ(pid.step(200 * kQ8, 190 * kQ8 + n), fresh.step(200 * kQ8, 190 * kQ8 + n));
}

TEST(Pid, RetuningAtSteadyStateDoesNotBump) {
  // The integrator holds output units, so new gains at zero error leave the output in place.
  Pid pid = configured(5, 0.5, 0);
  for (int n = 0; n < 300; ++n) pid.step(200 * kQ8, 199 * kQ8);
  const uint16_t before = pid.step(200 * kQ8, 200 * kQ8);
  pid.configure(gains(30, 3, 80), kPeriodMs);
  EXPECT_EQ(pid.step(200 * kQ8, 200 * kQ8), before);
}

TEST(Pid, ScheduledCoefficientsActLikeConfiguredGains) {
  // Configured for the largest gains a schedule reaches, then switched per step without division.
  Pid scheduled = configured(40, 3, 200);
  const PidGains g = gains(22.2, 1.08, 114);
  scheduled.set_coefficients(Pid::coefficients(g, kPeriodMs));
  Pid plain;
  plain.configure(g, kPeriodMs);
  for (int n = 0; n < 200; ++n) {
    const int32_t m = (150 + n / 3) * kQ8 + 37 * (n % 5);
    ASSERT_EQ(scheduled.step(210 * kQ8, m), plain.step(210 * kQ8, m)) << n;
  }
}

TEST(Pid, ScheduledCoefficientsAreCappedAtTheConfiguredOnes) {
  // Beyond configure()'s coefficients the overflow clamps would not hold: capped instead. These
  // gains map to whole-number coefficients (Kp·257, Ki·h·257·256, Kd/h·257 ≥ 1024), so the cap
  // reproduces them exactly.
  const PidGains g = gains(22.2, 1.08, 114);
  Pid capped;
  capped.configure(g, kPeriodMs);
  capped.set_coefficients(Pid::coefficients(gains(900, 90, 9000), kPeriodMs));
  Pid plain;
  plain.configure(g, kPeriodMs);
  for (int n = 0; n < 200; ++n) {
    const int32_t m = (25 + n) * kQ8;
    ASSERT_EQ(capped.step(210 * kQ8, m), plain.step(210 * kQ8, m)) << n;
  }
}

TEST(Pid, ControllerInterfaceStepsTheSameLaw) {
  Pid a = configured(22.2, 1.08, 114);
  Pid b = configured(22.2, 1.08, 114);
  control::Controller& c = b;
  for (int n = 0; n < 50; ++n) {
    const int32_t m = (25 + 3 * n) * kQ8;
    EXPECT_EQ(a.step(210 * kQ8, m), c.step(control::StepInput{210 * kQ8, m, 0}));
  }
}

}  // namespace
