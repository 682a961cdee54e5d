// The model feedforward (control/feedforward.h): exact against the double formula, limits, and
// what it buys in closed loop (a PID with fan feedforward rides through a part-fan step).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "control/feedforward.h"
#include "control/pid.h"
#include "host_tests/hotend40w_model.h"

namespace {

using control::Feedforward;
using control::HotendModel;
using test_plant::to_q8;

HotendModel model(double a, double c, double d, double f) {
  return {to_q8(a), to_q8(c), to_q8(d), to_q8(f)};
}

double expected_duty(const HotendModel& m, double target_c, int fan) {
  const double rise = std::max(0.0, target_c - 25.0);
  const double duty = rise / (m.rise_q8 / 256.0) * (1.0 + m.fan_loss_pct_q8 / 256.0 / 100.0 * fan / 255.0);
  return std::min(duty, 1.0) * 65535.0;
}

TEST(Feedforward, Hotend40wDefaultsComeFromThePhysicalModel) {
  const HotendModel m = control::kHotend40wModel;
  EXPECT_NEAR(m.rise_q8 / 256.0, 40.0 / 0.068, 0.002);
  EXPECT_NEAR(m.time_constant_q8 / 256.0, 16.7 / 0.068, 0.002);
  EXPECT_NEAR(m.dead_time_q8 / 256.0, 1 / 0.22, 0.002);
  EXPECT_NEAR(m.fan_loss_pct_q8 / 256.0, 42.647, 0.002);
  EXPECT_TRUE(control::hotend_model_valid(m));
}

TEST(Feedforward, MatchesTheDoubleFormula) {
  for (const HotendModel& m : {control::kHotend40wModel, model(450, 24, 20.7, 0), model(10, 1, 0, 500),
                               model(2000, 3600, 600, 123.45), model(300.5, 100, 10, 0.01)}) {
    Feedforward ff;
    ff.configure(m);
    for (double target : {0.0, 20.0, 25.0, 25.5, 100.0, 180.0, 210.0, 237.3, 275.0}) {
      for (int fan : {0, 1, 64, 127, 200, 255}) {
        const double want = expected_duty(m, target, fan);
        // Two roundings (base, then the fan part): within 2 LSB of 65535.
        EXPECT_NEAR(ff.duty_q16(to_q8(target), static_cast<uint8_t>(fan)), want, 2.0 + want * 2e-5)
            << "A " << m.rise_q8 / 256.0 << " target " << target << " fan " << fan;
      }
    }
  }
}

TEST(Feedforward, IsZeroAtAmbientAndClampedAtFullPower) {
  Feedforward ff;
  ff.configure(model(100, 100, 5, 50));
  EXPECT_EQ(ff.duty_q16(to_q8(25), 255), 0);
  EXPECT_EQ(ff.duty_q16(to_q8(-40), 255), 0);
  EXPECT_EQ(ff.duty_q16(to_q8(125), 0), 65535);  // exactly the full-power rise
  EXPECT_EQ(ff.duty_q16(to_q8(275), 255), 65535);
  EXPECT_LT(ff.duty_q16(to_q8(124), 0), 65535);
}

TEST(Feedforward, ModelRangesAreChecked) {
  EXPECT_TRUE(control::hotend_model_valid(model(10, 1, 0, 0)));
  EXPECT_TRUE(control::hotend_model_valid(model(2000, 3600, 600, 500)));
  EXPECT_FALSE(control::hotend_model_valid(model(9.99, 100, 5, 0)));
  EXPECT_FALSE(control::hotend_model_valid(model(2000.01, 100, 5, 0)));
  EXPECT_FALSE(control::hotend_model_valid(model(500, 0.99, 5, 0)));
  EXPECT_FALSE(control::hotend_model_valid(model(500, 3600.01, 5, 0)));
  EXPECT_FALSE(control::hotend_model_valid(model(500, 100, -0.01, 0)));
  EXPECT_FALSE(control::hotend_model_valid(model(500, 100, 600.01, 0)));
  EXPECT_FALSE(control::hotend_model_valid(model(500, 100, 5, -0.01)));
  EXPECT_FALSE(control::hotend_model_valid(model(500, 100, 5, 500.01)));
}

// Holds 210 °C on hotend40w with the PID, switches the part fan to 100 % at 400 s and returns
// the largest dip below the target afterwards (°C).
double fan_step_dip(bool use_feedforward) {
  control::Pid pid;
  pid.configure({34 << 16, 1 << 16, 100 << 16}, 128);  // issue 2's hotend40w defaults
  Feedforward ff;
  ff.configure(control::kHotend40wModel);
  test_plant::Hotend40w plant;
  plant.settle_at(210.0);
  pid.init_bumpless(to_q8(210.0), static_cast<uint16_t>(65535 * 185 / 588.2));
  double dip = 0;
  for (int k = 0; k < 6000; ++k) {
    const bool fan_on = k >= 3125;
    plant.set_fan(fan_on ? 1.0 : 0.0);
    if (use_feedforward) pid.set_feedforward(ff.duty_q16(to_q8(210.0), fan_on ? 255 : 0));
    plant.advance(pid.step(to_q8(210.0), to_q8(plant.sensor_c())) / 65535.0);
    if (fan_on) dip = std::max(dip, 210.0 - plant.sensor_c());
  }
  EXPECT_NEAR(plant.sensor_c(), 210.0, 0.05);  // either way the integral removes the offset
  return dip;
}

TEST(FeedforwardClosedLoop, FanFeedforwardShrinksThePartFanDip) {
  const double without = fan_step_dip(false);
  const double with = fan_step_dip(true);
  EXPECT_GT(without, 0.5);  // the disturbance is real
  EXPECT_LT(with, without / 3);
}

}  // namespace
