// control/steady_hold.h: the static gain K from a steady hold, against the double-precision
// (mean reading − 25 °C) / mean duty, and the conditions that make a hold count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>

#include "control/steady_hold.h"

namespace {

using control::SteadyHold;

constexpr int kWindow = SteadyHold::kWindowPeriods;

// One window of periods at target_c, the readings and duties drawn around the given means (a
// controller's ripple: ± spread), fan off unless given. Returns the double-precision K.
double feed(SteadyHold& h, double target_c, double temp_c, double duty, int periods = kWindow,
            double temp_spread = 0.3, double duty_spread = 0.05, uint8_t fan = 0) {
  double sum_t = 0, sum_u = 0;
  for (int i = 0; i < periods; ++i) {
    const double wobble = std::sin(i * 0.37);
    const int32_t t_q8 = static_cast<int32_t>(std::lround((temp_c + temp_spread * wobble) * 256));
    const double u = std::min(1.0, std::max(0.0, duty - duty_spread * wobble));
    const uint16_t u_q16 = static_cast<uint16_t>(std::lround(u * 65535));
    sum_t += t_q8 / 256.0;
    sum_u += u_q16 / 65535.0;
    h.update(static_cast<int32_t>(std::lround(target_c * 256)), t_q8, u_q16, fan);
  }
  return (sum_t / periods - 25.0) / (sum_u / periods);
}

TEST(SteadyHold, GainWithinHalfAPercentOfTheDoublePrecisionMeanOverTheBanksRange) {
  // Worst relative error over targets 150–275 °C and duties 2–100 % (K 50–4,000 °C within range).
  double worst = 0;
  for (double target : {150.0, 200.0, 240.0, 275.0}) {
    for (double duty : {0.03, 0.08, 0.157, 0.315, 0.41, 0.7, 0.95}) {
      SteadyHold h;
      const double k = feed(h, target, target + 0.1, duty, kWindow, 0.3, duty * 0.2);
      const double got = h.static_gain_q8() / 256.0;
      if (k < 50 || k > 4000) {
        EXPECT_EQ(h.static_gain_q8(), 0) << target << " °C at " << duty;
        continue;
      }
      const double err = std::fabs(got - k) / k;
      worst = std::max(worst, err);
      EXPECT_LT(err, 0.005) << target << " °C at " << duty << ": " << got << " against " << k;
    }
  }
  std::printf("SteadyHold: worst |K − K_double| / K %.4f %%\n", worst * 100);
}

TEST(SteadyHold, NoGainBeforeAWholeWindow) {
  SteadyHold h;
  feed(h, 210, 210, 0.315, kWindow - 1);
  EXPECT_EQ(h.static_gain_q8(), 0);
  feed(h, 210, 210, 0.315, 1);
  EXPECT_NEAR(h.static_gain_q8() / 256.0, 185 / 0.315, 2.0);
}

TEST(SteadyHold, AReadingOutsideOneDegreeTheFanOrATargetChangeStartsTheWindowAgain) {
  SteadyHold h;
  feed(h, 210, 210, 0.315, kWindow - 10);
  h.update(210 * 256, 211 * 256 + 2, 20000, 0);  // 1.008 °C above: not holding
  feed(h, 210, 210, 0.315, kWindow - 1);
  EXPECT_EQ(h.static_gain_q8(), 0);

  SteadyHold fan;
  feed(fan, 210, 210, 0.315, kWindow - 10);
  feed(fan, 210, 210, 0.45, 1, 0, 0, 255);  // the part fan on for one period
  feed(fan, 210, 210, 0.315, kWindow - 1);
  EXPECT_EQ(fan.static_gain_q8(), 0);

  SteadyHold retarget;
  feed(retarget, 210, 210, 0.315, kWindow - 10);
  feed(retarget, 215, 215, 0.33, kWindow - 1);
  EXPECT_EQ(retarget.static_gain_q8(), 0);

  SteadyHold off;  // heater off (target 0) is no hold, whatever the reading
  feed(off, 0, 0.5, 0.0, kWindow * 2, 0, 0);
  EXPECT_EQ(off.static_gain_q8(), 0);
}

TEST(SteadyHold, AWindowsGainStaysThroughLaterChangesUntilReset) {
  SteadyHold h;
  feed(h, 200, 200, 0.3, kWindow);
  const int32_t k = h.static_gain_q8();
  ASSERT_NEAR(k / 256.0, 175 / 0.3, 2.0);
  feed(h, 240, 230, 1.0, 100, 0, 0);  // a new target, heating at full power
  feed(h, 240, 240, 0.4, 100, 0, 0, 128);
  EXPECT_EQ(h.static_gain_q8(), k);
  h.reset();
  EXPECT_EQ(h.static_gain_q8(), 0);
}

TEST(SteadyHold, NoGainFromATinyDutyOrOutsideTheRange) {
  SteadyHold tiny;  // 1.5 % holds 60 °C: below 2 % the duty's rounding is too coarse
  feed(tiny, 60, 60, 0.015, kWindow, 0.3, 0.001);
  EXPECT_EQ(tiny.static_gain_q8(), 0);
  SteadyHold weak;  // 100 % holding 60 °C: K 35 °C, below the 50 °C floor
  feed(weak, 60, 60, 1.0, kWindow, 0.3, 0.0);
  EXPECT_EQ(weak.static_gain_q8(), 0);
  SteadyHold below;  // a hold at or below 25 °C gives no rise to divide
  feed(below, 20, 20, 0.1, kWindow, 0.3, 0.0);
  EXPECT_EQ(below.static_gain_q8(), 0);
}

}  // namespace
