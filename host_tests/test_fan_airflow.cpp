// The part fan's airflow estimate (control/fan_airflow.h) the controllers' fan feedforward sees.
#include <gtest/gtest.h>

#include <cmath>

#include "control/fan_airflow.h"

namespace {

// First order with τ = 0.128 s / ln(4/3) ≈ 0.445 s: after a 0 → 255 step, 1 − (3/4)^k of the way
// after k periods (within the Q6 rounding), never past the pin.
TEST(FanAirflow, FollowsAStepAsAFirstOrderLag) {
  control::FanAirflow f;
  EXPECT_EQ(f.airflow(), 0);
  for (int k = 1; k <= 40; ++k) {
    f.step(255);
    const double want = 255 * (1 - std::pow(0.75, k));
    EXPECT_NEAR(f.airflow(), want, 1.5) << k;
    EXPECT_LE(f.airflow(), 255);
  }
  EXPECT_EQ(f.airflow(), 255);
}

// Every pin duty is reached exactly from every start (no dead band from the integer shift).
TEST(FanAirflow, SettlesExactlyOnEveryDuty) {
  for (int from = 0; from <= 255; from += 15) {
    for (int to = 0; to <= 255; ++to) {
      control::FanAirflow f;
      for (int k = 0; k < 60; ++k) f.step(static_cast<uint8_t>(from));
      ASSERT_EQ(f.airflow(), from);
      for (int k = 0; k < 60; ++k) f.step(static_cast<uint8_t>(to));
      ASSERT_EQ(f.airflow(), to) << from << " -> " << to;
    }
  }
}

// M106 between two periods: retarget() gives the next period the airflow step() would have
// given with the new duty, and the following steps continue from there.
TEST(FanAirflow, RetargetRedoesTheLastStep) {
  control::FanAirflow a, b;
  for (int k = 0; k < 10; ++k) {
    a.step(100);
    b.step(100);
  }
  a.step(100);
  a.retarget(255);
  b.step(255);
  EXPECT_EQ(a.airflow(), b.airflow());
  for (int k = 0; k < 5; ++k) {
    a.step(255);
    b.step(255);
    EXPECT_EQ(a.airflow(), b.airflow());
  }
}

}  // namespace
