// The fuzzy-PID controller: supervisor inputs and gain schedule, and closed loop on the physical
// two-node hotend (issue 2's hotend40w) against a double-precision fuzzy-PID using the direct
// Mamdani evaluation.
#include "control/fuzzy_pid.h"
#include "design/fuzzy_reference.h"
#include "control/fuzzy_surface_gen.h"
#include "host_tests/closed_loop.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

namespace {

using control::FuzzyPid;
using control::FuzzyPidConfig;
using control::PidGains;

constexpr uint16_t kPeriodMs = 128;  // the firmware's control period
constexpr double kPeriodS = kPeriodMs / 1000.0;
constexpr double kAmbientC = 25.0;

constexpr auto kSurfaces = fuzzy::make_default_surfaces();
fuzzy::Cell load_cell(uint16_t i) { return kSurfaces.cell[i]; }

PidGains q16_gains(double kp, double ki, double kd) {
  return {int32_t(std::lround(kp * 65536)), int32_t(std::lround(ki * 65536)), int32_t(std::lround(kd * 65536))};
}
double gain(int32_t q16) { return q16 / 65536.0; }

// Marlin's stock E3D-class hotend gains (Configuration.h DEFAULT_Kp/Ki/Kd 22.2, 1.08, 114).
const PidGains kMarlinE3d = q16_gains(22.2, 1.08, 114.0);
const FuzzyPidConfig kDefault = control::fuzzy_config_around(kMarlinE3d, control::kDefaultFuzzySpreadPct);

// issue 2's hotend40w (host_tests/hotend40w_model.h).
using TwoNodeHotend = test_plant::Hotend40w;

// The same controller in double: ec filter, direct Mamdani (not the interpolated grid), and the
// algorithm of control/pid.h (conditional integration, filtered derivative on measurement).
class ReferenceFuzzyPid {
 public:
  explicit ReferenceFuzzyPid(const FuzzyPidConfig& c) : c_(c) {}
  double step(double target_c, double measured_c) {
    const double e = target_c - measured_c;
    const double change = have_previous_ ? measured_c - previous_c_ : 0.0;
    previous_c_ = measured_c;
    have_previous_ = true;
    change_ += (change - change_) / 4;  // FuzzyPid's α = 1/4
    const double e_u = fuzzy::reference::quantize(c_.e_factor_q12 / 4096.0, e);
    const double ec_u = fuzzy::reference::quantize(c_.ec_factor_q12 / 4096.0, -change_ / kPeriodS);
    const double kp = gain(c_.base.kp_q16) + gain(c_.scale.kp_q16) * fuzzy::reference::mamdani(fuzzy::kRulesKp, e_u, ec_u, 600);
    const double ki = gain(c_.base.ki_q16) + gain(c_.scale.ki_q16) * fuzzy::reference::mamdani(fuzzy::kRulesKi, e_u, ec_u, 600);
    const double kd = gain(c_.base.kd_q16) + gain(c_.scale.kd_q16) * fuzzy::reference::mamdani(fuzzy::kRulesKd, e_u, ec_u, 600);
    const double alpha = kPeriodS / (control::Pid::kDefaultDerivativeFilterMs / 1000.0 + kPeriodS);
    d_ += alpha * (-kd / 255 * change / kPeriodS - d_);
    const double p = kp / 255 * e, increment = ki / 255 * kPeriodS * e, before = p + i_ + d_;
    if ((increment > 0 && before < 1) || (increment < 0 && before > 0)) i_ += increment;
    i_ = std::min(std::max(i_, 0.0), 1.0);
    return std::min(std::max(p + i_ + d_, 0.0), 1.0);
  }

 private:
  FuzzyPidConfig c_;
  double change_ = 0, previous_c_ = 0, i_ = 0, d_ = 0;
  bool have_previous_ = false;
};

using test_plant::Trajectory;

// Closed loop for `seconds`; `fan_at_s` switches the part fan to 100 % (more loss) at that time.
template <class Control> Trajectory run(Control control, double seconds, double fan_at_s = 1e9) {
  return test_plant::run_closed_loop(TwoNodeHotend{}, control, seconds, [fan_at_s](int k, TwoNodeHotend& plant) {
    if (k * kPeriodS >= fan_at_s) plant.set_fan(1.0);
  });
}

Trajectory run_fixed(const FuzzyPidConfig& config, double target_c, double seconds, double fan_at_s = 1e9) {
  FuzzyPid pid(load_cell);
  EXPECT_TRUE(FuzzyPid::valid(config, kPeriodMs));
  pid.configure(config, kPeriodMs);
  const int32_t target_q8 = int32_t(std::lround(target_c * 256));
  return run([&](double m) {
    return pid.step(control::StepInput{target_q8, int32_t(std::lround(m * 256)), 0}) / 65535.0;
  }, seconds, fan_at_s);
}

// Mean and peak |error| over the samples from `from_s` to `to_s`.
struct Window {
  double mean_error_c = 0, max_abs_error_c = 0;
};
Window window(const Trajectory& t, double target_c, double from_s, double to_s) {
  Window w;
  int n = 0;
  for (size_t k = size_t(from_s / kPeriodS); k < t.temp_c.size() && k < size_t(to_s / kPeriodS); ++k, ++n) {
    w.mean_error_c += t.temp_c[k] - target_c;
    w.max_abs_error_c = std::max(w.max_abs_error_c, std::fabs(t.temp_c[k] - target_c));
  }
  w.mean_error_c /= n;
  return w;
}

TEST(FuzzyPid, SupervisorInputsFollowTheSeedQuantization) {
  FuzzyPid pid(load_cell);
  pid.configure(kDefault, kPeriodMs);
  pid.step({210 * 256, 200 * 256, 0});  // 10 °C below target: beyond 7.5 °C, e saturates
  EXPECT_EQ(pid.last_e_u_q8(), 768);
  EXPECT_EQ(pid.last_ec_u_q8(), 0);  // no history yet: no rate
  pid.reset();
  pid.step({210 * 256, 208 * 256, 0});  // 2 °C below: 0.4 × 2 = 0.8 universe
  EXPECT_NEAR(pid.last_e_u_q8() / 256.0, 0.8, 0.005);
  // Rising 0.128 °C per 128 ms period = 1 °C/s: after the low-pass settles, ec = −1 °C/s → −0.6.
  for (int k = 1; k <= 40; ++k) pid.step({210 * 256, 208 * 256 + k * 256 * 128 / 1000, 0});
  EXPECT_NEAR(pid.last_ec_u_q8() / 256.0, -0.6, 0.02);
}

TEST(FuzzyPid, ANewTargetDoesNotKickTheErrorRate) {
  FuzzyPid pid(load_cell);
  pid.configure(kDefault, kPeriodMs);
  for (int k = 0; k < 20; ++k) pid.step({200 * 256, 200 * 256, 0});
  pid.step({240 * 256, 200 * 256, 0});  // a 40 °C setpoint step at constant temperature
  EXPECT_EQ(pid.last_ec_u_q8(), 0);
}

TEST(FuzzyPid, GainsFollowTheScheduleFarFromAndAtTheTarget) {
  FuzzyPid pid(load_cell);
  pid.configure(kDefault, kPeriodMs);
  // Expected gain = base + scale·Δ; the grid stores Δ in Q6, so allow scale·½/64 (+ rounding).
  auto expect_gains = [&](double dkp, double dki, double dkd) {
    const PidGains g = pid.last_gains();
    EXPECT_NEAR(gain(g.kp_q16), gain(kDefault.base.kp_q16) + gain(kDefault.scale.kp_q16) * dkp,
                gain(kDefault.scale.kp_q16) / 128 + 1e-3);
    EXPECT_NEAR(gain(g.ki_q16), gain(kDefault.base.ki_q16) + gain(kDefault.scale.ki_q16) * dki,
                gain(kDefault.scale.ki_q16) / 128 + 1e-4);
    EXPECT_NEAR(gain(g.kd_q16), gain(kDefault.base.kd_q16) + gain(kDefault.scale.kd_q16) * dkd,
                gain(kDefault.scale.kd_q16) / 128 + 1e-3);
  };
  const double lo = 1.0 / 6, hi = 3 - 1.0 / 6;  // centroids of the end half-triangles NB, PB
  // One supervisor cycle (four steps: inputs, surfaces, kp/ki, kd) at each operating point.
  for (int k = 0; k < 4; ++k) pid.step({210 * 256, 100 * 256, 0});  // far below, steady (row e PB, ec ZO)
  expect_gains(hi, lo, lo);                                          // kp PB, ki NB, kd NB
  pid.reset();
  for (int k = 0; k < 4; ++k) pid.step({210 * 256, 210 * 256, 0});  // on target, steady (row e ZO, ec ZO)
  expect_gains(2.0, hi, hi);                                         // kp PS, ki PB, kd PB
  // The nominal gains sit mid-schedule: Δ = 1.5 gives them back (fuzzy_config_around).
  EXPECT_NEAR(gain(kDefault.base.kp_q16) + 1.5 * gain(kDefault.scale.kp_q16), 22.2, 1e-3);
  EXPECT_NEAR(gain(kDefault.base.ki_q16) + 1.5 * gain(kDefault.scale.ki_q16), 1.08, 1e-4);
  EXPECT_NEAR(gain(kDefault.base.kd_q16) + 1.5 * gain(kDefault.scale.kd_q16), 114.0, 1e-3);
}

TEST(FuzzyPid, ValidityCoversEveryReachableGain) {
  EXPECT_TRUE(FuzzyPid::valid(kDefault, kPeriodMs));
  EXPECT_TRUE(FuzzyPid::valid(control::fuzzy_seed002_config(kMarlinE3d), kPeriodMs));
  FuzzyPidConfig c = kDefault;
  c.scale.ki_q16 = -1;
  EXPECT_FALSE(FuzzyPid::valid(c, kPeriodMs));
  c = kDefault;
  c.scale.kp_q16 = control::Pid::kMaxKpQ16 / 3 + 65536;  // base + 3·scale beyond the PID's range
  EXPECT_FALSE(FuzzyPid::valid(c, kPeriodMs));
  c = kDefault;
  c.e_factor_q12 = 0;
  EXPECT_FALSE(FuzzyPid::valid(c, kPeriodMs));
  EXPECT_FALSE(FuzzyPid::valid(kDefault, 10));  // ec factor per 10 ms period overflows Q12
}

TEST(FuzzyPid, TakesOverBumplessly) {
  FuzzyPid pid(load_cell);
  pid.configure(kDefault, kPeriodMs);
  // 1 °C below target, so that P alone (≈ 0.1 of full power) is below the duty taken over.
  pid.init_bumpless(209 * 256, 20000);
  const uint16_t first = pid.step({210 * 256, 209 * 256, 0});
  EXPECT_NEAR(first, 20000, 100);  // only this step's own integration moves it (Ki·h·e ≈ 50)
}

// Time after which the temperature stays within ±band of the target.
double settling_s(const Trajectory& t, double target_c, double band_c) {
  size_t last_out = 0;
  for (size_t k = 0; k < t.temp_c.size(); ++k)
    if (std::fabs(t.temp_c[k] - target_c) > band_c) last_out = k + 1;
  return last_out * kPeriodS;
}

TEST(FuzzyPidClosedLoop, HeatsHotend40wWithoutOvershootOrOffset) {
  const Trajectory t = run_fixed(kDefault, 210.0, 600.0);
  const Window hold = window(t, 210.0, 500.0, 600.0);
  const double steady_duty = 0.068 * (210.0 - kAmbientC) / 40.0;  // what 210 °C needs physically
  // The plain PID with the nominal gains, for comparison (printed; the PID has its own tests).
  control::Pid plain;
  plain.configure(kMarlinE3d, kPeriodMs);
  const Trajectory p = run([&](double m) { return plain.step(210 * 256, int32_t(std::lround(m * 256))) / 65535.0; }, 600.0);
  std::printf("  hotend40w 25→210 °C   overshoot   settle ±1 °C   settle ±0.1 °C\n"
              "  fuzzy-PID            %6.2f °C   %8.1f s     %8.1f s\n"
              "  PID (nominal gains)  %6.2f °C   %8.1f s     %8.1f s\n",
              t.max_c - 210.0, settling_s(t, 210.0, 1.0), settling_s(t, 210.0, 0.1), p.max_c - 210.0,
              settling_s(p, 210.0, 1.0), settling_s(p, 210.0, 0.1));
  EXPECT_LT(t.max_c - 210.0, 1.0);
  EXPECT_LT(std::fabs(hold.mean_error_c), 0.02);
  EXPECT_LT(hold.max_abs_error_c, 0.05);
  EXPECT_NEAR(t.duty.back(), steady_duty, 0.01);
  EXPECT_EQ(*std::max_element(t.duty.begin(), t.duty.begin() + 100), 1.0);  // full power while cold
}

TEST(FuzzyPidClosedLoop, RecoversFromAPartFanStep) {
  const Trajectory t = run_fixed(kDefault, 210.0, 800.0, 500.0);
  const Window dip = window(t, 210.0, 500.0, 800.0);
  const Window after = window(t, 210.0, 700.0, 800.0);
  std::printf("  fan 0→100 %% at 500 s: max |error| %.2f °C, mean error %.4f °C over 700–800 s\n",
              dip.max_abs_error_c, after.mean_error_c);
  EXPECT_GT(dip.max_abs_error_c, 0.3);  // the disturbance is real
  EXPECT_LT(dip.max_abs_error_c, 3.0);
  EXPECT_LT(std::fabs(after.mean_error_c), 0.05);
  EXPECT_NEAR(t.duty.back(), 0.097 * (210.0 - kAmbientC) / 40.0, 0.01);
}

TEST(FuzzyPidClosedLoop, HoldsTheTargetThroughSensorNoise) {
  // White noise of σ 0.1 °C on every reading (worse than 128× oversampling of a 10-bit ADC): the
  // schedule's kd peaks on target (PB), so the duty ripples more than a plain PID's, but the
  // hotend itself must stay put.
  std::mt19937 rng(1);
  std::normal_distribution<double> noise_c(0.0, 0.1);
  FuzzyPid pid(load_cell);
  pid.configure(kDefault, kPeriodMs);
  const Trajectory t = run([&](double m) {
    return pid.step(control::StepInput{210 * 256, int32_t(std::lround((m + noise_c(rng)) * 256)), 0}) / 65535.0;
  }, 600.0);
  const Window hold = window(t, 210.0, 400.0, 600.0);
  std::printf("  sensor noise σ 0.1 °C: true temperature max |error| %.3f °C, mean %.4f °C over 400–600 s\n",
              hold.max_abs_error_c, hold.mean_error_c);
  EXPECT_LT(hold.max_abs_error_c, 0.1);
  EXPECT_LT(std::fabs(hold.mean_error_c), 0.01);
  EXPECT_LT(t.max_c - 210.0, 1.0);
}

TEST(FuzzyPidClosedLoop, SeedScaleFactorsAlsoHoldTheTarget) {
  const Trajectory t = run_fixed(control::fuzzy_seed002_config(kMarlinE3d), 210.0, 600.0);
  const Window hold = window(t, 210.0, 500.0, 600.0);
  std::printf("  seed 002 scales (s = 1): overshoot %.2f °C, mean error %.4f °C\n", t.max_c - 210.0,
              hold.mean_error_c);
  EXPECT_LT(t.max_c - 210.0, 3.0);
  EXPECT_LT(std::fabs(hold.mean_error_c), 0.02);
}

TEST(FuzzyPidClosedLoop, FixedPointTracksTheDoubleReference) {
  const Trajectory fixed = run_fixed(kDefault, 210.0, 600.0);
  ReferenceFuzzyPid ref(kDefault);
  const Trajectory exact = run([&](double m) { return ref.step(210.0, m); }, 600.0);
  double dt = 0, dd = 0;
  for (size_t k = 0; k < fixed.temp_c.size(); ++k) {
    dt = std::max(dt, std::fabs(fixed.temp_c[k] - exact.temp_c[k]));
    dd = std::max(dd, std::fabs(fixed.duty[k] - exact.duty[k]));
  }
  std::printf("  fixed vs double fuzzy-PID: max |ΔT| %.3f °C, max |Δduty| %.2f %%, overshoot %.2f / %.2f °C\n", dt,
              100 * dd, fixed.max_c - 210.0, exact.max_c - 210.0);
  EXPECT_LT(dt, 0.5);
  EXPECT_LT(std::fabs(fixed.max_c - exact.max_c), 0.3);
  EXPECT_NEAR(fixed.temp_c.back(), exact.temp_c.back(), 0.05);
}

}  // namespace

namespace {

double coefficient(const fixed::Multiplier& m) { return m.whole + m.frac_q16 / 65536.0; }

// The per-step schedule (base and scale coefficients combined with multiplies) against the
// exact coefficients of the scheduled gains, in Pid's internal units (pid.cpp): Kp·257,
// Ki·h·257·256, Kd/h·257 — at every supervisor output the closed loop visits.
TEST(FuzzyPid, ScheduledCoefficientsAreThoseOfTheScheduledGains) {
  for (const FuzzyPidConfig& config : {kDefault, control::fuzzy_seed002_config(kMarlinE3d),
                                       control::fuzzy_config_around(q16_gains(3.1, 0.02, 40), 90)}) {
    FuzzyPid fuzzy(load_cell);
    ASSERT_TRUE(FuzzyPid::valid(config, kPeriodMs));
    fuzzy.configure(config, kPeriodMs);
    TwoNodeHotend plant;
    for (int k = 0; k < 4000; ++k) {
      const uint16_t duty = fuzzy.step({210 * 256, int32_t(std::lround(plant.sensor_c() * 256)), 0});
      plant.advance(duty / 65535.0, kPeriodS);
      const fuzzy::Deltas d = fuzzy.last_deltas();
      const control::PidCoefficients c = fuzzy.last_coefficients();
      const double kp = gain(config.base.kp_q16) + gain(config.scale.kp_q16) * d.dkp_q8 / 256.0;
      const double ki = gain(config.base.ki_q16) + gain(config.scale.ki_q16) * d.dki_q8 / 256.0;
      const double kd = gain(config.base.kd_q16) + gain(config.scale.kd_q16) * d.dkd_q8 / 256.0;
      // Exact to 2^-16 while every part is below 1024. Pid::coefficients() rounds coefficients
      // ≥ 1024 to whole units (≤ 2^-11 relative): base ±½, scale ±½ · Δ (≤ 3), the sum ±½.
      auto tolerance = [](double x) { return x < 1024 ? 3.0 / 65536 : 2.5; };
      const double want_p = kp * 257, want_i = ki * kPeriodS * 257 * 256, want_d = kd / kPeriodS * 257;
      ASSERT_NEAR(coefficient(c.kp), want_p, tolerance(want_p)) << k;
      ASSERT_NEAR(coefficient(c.ki), want_i, tolerance(want_i)) << k;
      ASSERT_NEAR(coefficient(c.kd), want_d, tolerance(want_d)) << k;
    }
  }
}

}  // namespace
