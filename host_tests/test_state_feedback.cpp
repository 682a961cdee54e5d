// The fixed-point state-feedback runtime: its product primitive, its constants, and its
// behaviour as a Controller (priming, decimation, bumpless start, bad constants).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <initializer_list>

#include "control/state_feedback_math.h"
#include "host_tests/test_state_feedback_loop.h"

namespace {

using namespace sf_test;

TEST(StateFeedbackMath, MulHi16IsTheRounded48BitProduct) {
  uint32_t s = 12345;
  auto next = [&s] { return s = s * 1664525u + 1013904223u; };
  for (int i = 0; i < 200000; ++i) {
    int16_t m = static_cast<int16_t>(next() >> 16);
    if (m == -32768) m = -32767;  // the design never emits it
    int32_t x = static_cast<int32_t>(next());
    if (i & 1) x >>= next() & 31;
    const int64_t want = (static_cast<int64_t>(m) * x + 0x8000) >> 16;
    ASSERT_EQ(control::sf::mulhi16(m, x), want) << m << " * " << x;
  }
}

TEST(StateFeedback, QuantisedConstantsAreValidForEveryPlant) {
  for (int i = 0; i < kPlantCount; ++i) {
    const Plant p = plant(i);
    SCOPED_TRACE(p.name);
    Loop loop(p, Scenario());
    ASSERT_EQ(loop.error(), nullptr);
    const control::StateFeedbackConstants& k = loop.constants();
    EXPECT_TRUE(control::state_feedback_constants_valid(k));
    EXPECT_EQ(k.n, p.model.n);
    EXPECT_GE(k.decimation, 2);
    control::StateFeedback sf;
    EXPECT_TRUE(sf.configure(k));
  }
}

TEST(StateFeedback, RejectsConstantsOutsideItsRangeAndKeepsTheOldOnes) {
  Loop loop(plant(3), Scenario());
  control::StateFeedback sf;
  ASSERT_TRUE(sf.configure(loop.constants()));
  control::StateFeedbackConstants bad = loop.constants();
  bad.n = 0;
  EXPECT_FALSE(sf.configure(bad));
  bad = loop.constants();
  bad.decimation = 1;  // no call left for the time update
  EXPECT_FALSE(sf.configure(bad));
  bad = loop.constants();
  bad.delay = 20;  // 20 taps need two predictor calls: decimation >= 4
  bad.decimation = 3;
  EXPECT_FALSE(sf.configure(bad));
  bad = loop.constants();
  bad.output_mask = 0x10;  // a state that does not exist
  EXPECT_FALSE(sf.configure(bad));
  EXPECT_EQ(sf.constants().n, loop.constants().n);
  EXPECT_TRUE(sf.configured());
}

TEST(StateFeedback, UnconfiguredControllerKeepsTheHeaterOff) {
  control::StateFeedback sf;
  EXPECT_EQ(sf.step({210 * 256, 25 * 256, 0}), 0);
}

// After reset the first call only primes (heater stays off); then the duty changes only once
// per law period and is held in between.
TEST(StateFeedback, PrimesThenHoldsTheDutyForTheLawPeriod) {
  Loop loop(plant(0), Scenario());  // seed002: law every 6 calls, predictor first
  control::StateFeedback& sf = loop.controller();
  ASSERT_TRUE(sf.configure(loop.constants()));
  const uint8_t n = loop.constants().decimation;
  EXPECT_EQ(sf.step({210 * 256, 25 * 256, 0}), 0);  // priming
  uint16_t last = 0;
  int changes = 0;
  for (int k = 0; k < 10 * n; ++k) {
    const uint16_t u = sf.step({static_cast<int32_t>(210 * 256 - k), 25 * 256 + k, 0});
    if (u != last) {
      ++changes;
      EXPECT_EQ((k - (n - 2)) % n, 0) << "changed at call " << k;
    }
    last = u;
  }
  EXPECT_GE(changes, 1);
  EXPECT_EQ(last, 65535);  // far below target: full power
}

// A fan step between two law updates: the fan's share follows it in the law period's idle calls
// (seed002: law every 6 calls, 2 of them idle) and the law's part stays held. At the target
// the share is F·rise of duty (M307 F 42.6 %: ~0.175 at 210 °C); holding it to the next law
// update came back as a dip one dead time later.
TEST(StateFeedback, FanShareFollowsTheFanBetweenLawUpdates) {
  Loop loop(plant(0), Scenario());
  control::StateFeedback& sf = loop.controller();
  ASSERT_TRUE(sf.configure(loop.constants()));
  const control::StateFeedbackConstants& k = loop.constants();
  ASSERT_GT(k.decimation, control::state_feedback_min_decimation(k.delay));  // has idle calls
  ASSERT_NE(k.fan_gain, 0);
  const int32_t at_q8 = 210 * 256;
  const double steady = (210.0 - 25) / loop.design_result().dc_gain;
  sf.init_bumpless(at_q8, static_cast<uint16_t>(steady * 65535));
  // Run to a law update: priming starts the period at phase 2 (the predictor's chunks), so the
  // law runs at call decimation − 2 and every decimation calls after it.
  ASSERT_GT(k.delay, 0);
  uint16_t u = 0;
  for (int c = 0; c < 2 * k.decimation - 1; ++c) u = sf.step({at_q8, at_q8, 0});
  const uint16_t held = u;
  int first_change = -1;
  for (int c = 0; c < k.decimation; ++c) {
    u = sf.step({at_q8, at_q8, 255});
    if (u != held && first_change < 0) first_change = c;
  }
  // Within the same law period (not only at the next law update, call decimation − 1 or later).
  EXPECT_GE(first_change, 0);
  EXPECT_LT(first_change, k.decimation - 1);
  EXPECT_NEAR((u - held) / 65535.0, 0.426 * steady, 0.02);
  // And back when the fan stops, again before the next law update.
  for (int c = 0; c < k.decimation; ++c) u = sf.step({at_q8, at_q8, 0});
  EXPECT_NEAR(u, held, 700);
}

// Take-over from another controller at a steady temperature: the first law output is the duty
// that controller was giving, within 1 % of full scale.
TEST(StateFeedback, BumplessStartContinuesTheGivenDuty) {
  for (int i : {0, 3, 5}) {
    const Plant p = plant(i);
    SCOPED_TRACE(p.name);
    Loop loop(p, Scenario());
    control::StateFeedback& sf = loop.controller();
    ASSERT_TRUE(sf.configure(loop.constants()));
    const double steady_duty = (p.target_c - 25) / loop.design_result().dc_gain;
    const uint16_t duty = static_cast<uint16_t>(steady_duty * 65535);
    sf.init_bumpless(static_cast<int32_t>(p.target_c * 256), duty);
    uint16_t u = duty;
    for (int k = 0; k < loop.constants().decimation; ++k)
      u = sf.step(
          {static_cast<int32_t>(p.target_c * 256), static_cast<int32_t>(p.target_c * 256), 0});
    EXPECT_NEAR(u, duty, 655);
  }
}

// Reset at a hot temperature with the target below it: the observer starts from the measurement,
// so the heater stays off instead of reacting to a model that believes it is cold.
TEST(StateFeedback, ResetWhileHotStartsFromTheMeasurement) {
  Loop loop(plant(3), Scenario());
  control::StateFeedback& sf = loop.controller();
  ASSERT_TRUE(sf.configure(loop.constants()));
  sf.reset();
  for (int k = 0; k < 20; ++k) EXPECT_EQ(sf.step({150 * 256, 200 * 256, 0}), 0) << k;
  const int32_t sensor_rise_q16 = sf.state_q16(1);
  EXPECT_NEAR(sensor_rise_q16 / 65536.0, 175.0, 2.0);
}

}  // namespace
