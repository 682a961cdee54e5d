// FOPDT tuning rules against values worked out by hand, and the two-point identification.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "design/tuning.h"

namespace {

// Seed 002's dynamics with issue 2's gain (100 % duty settles 450 K up): K 450, T 24 s, τ 20.7 s.
// r = τ/T = 0.8625; 255/K = 0.56667.
const tuning::Fopdt kSeed002{450.0, 24.0, 20.7};

void expect_gains(const tuning::MarlinGains& g, double kp, double ki, double kd) {
  EXPECT_NEAR(g.kp, kp, 1e-9 + 1e-6 * kp);
  EXPECT_NEAR(g.ki, ki, 1e-9 + 1e-6 * ki);
  EXPECT_NEAR(g.kd, kd, 1e-9 + 1e-6 * kd);
}

TEST(Tuning, ZieglerNicholsStepResponse) {
  // Kc = 1.2·24/(450·20.7) = 0.0030918 → Kp = 0.788406; Ti = 41.4 s → Ki = 0.0190436;
  // Td = 10.35 s → Kd = 8.16.
  expect_gains(tuning::ziegler_nichols_step(kSeed002), 0.788406, 0.0190436, 8.16);
}

TEST(Tuning, CohenCoon) {
  // Kc = 24/(450·20.7)·(4/3 + 0.8625/4) = 0.0025765·1.549 → Kp = 1.017673;
  // Ti = 20.7·(32 + 5.175)/(13 + 6.9) = 38.66947 s → Ki = 0.0263172;
  // Td = 82.8/(11 + 1.725) = 6.506876 s → Kd = 6.621873.
  expect_gains(tuning::cohen_coon(kSeed002), 1.017673, 0.0263172, 6.621873);
}

TEST(Tuning, SimcWithDefaultAndChosenClosedLoopTimeConstant) {
  // τc = τ: Kc = 24/(450·41.4) → Kp = 0.3285024; Ti = min(24, 165.6) = 24 → Ki = 0.0136876; PI.
  expect_gains(tuning::simc(kSeed002), 0.3285024, 0.0136876, 0.0);
  // τc = 2τ (slower): Kc = 24/(450·62.1) → Kp = 0.2190016; Ti = 24 → Ki = 0.00912507.
  expect_gains(tuning::simc(kSeed002, 41.4), 0.2190016, 0.00912507, 0.0);
  // A short dead time makes 4(τc + τ) the smaller integral time: τ = τc = 2 s → Ti = 16 s.
  const tuning::MarlinGains fast = tuning::simc(tuning::Fopdt{450.0, 24.0, 2.0});
  EXPECT_NEAR(fast.kp / fast.ki, 16.0, 1e-12);
}

TEST(Tuning, Amigo) {
  // Kc = (0.2 + 0.45·24/20.7)/450 → Kp = 0.4089855; Ti = 20.7·(8.28 + 19.2)/(20.7 + 2.4)
  // = 24.62494 s → Ki = 0.0166086; Td = 0.5·20.7·24/(6.21 + 24) = 8.222443 s → Kd = 3.362860.
  expect_gains(tuning::amigo(kSeed002), 0.4089855, 0.0166086, 3.362860);
}

TEST(Tuning, EveryRuleGivesGainsTheFirmwarePidHolds) {
  for (const tuning::MarlinGains& g : {tuning::ziegler_nichols_step(kSeed002), tuning::cohen_coon(kSeed002),
                                       tuning::simc(kSeed002), tuning::amigo(kSeed002)}) {
    const control::PidGains q = tuning::to_q16(g);
    EXPECT_NEAR(q.kp_q16 / 65536.0, g.kp, 0.5 / 65536);
    EXPECT_NEAR(q.ki_q16 / 65536.0, g.ki, 0.5 / 65536);
    EXPECT_NEAR(q.kd_q16 / 65536.0, g.kd, 0.5 / 65536);
    EXPECT_TRUE(control::Pid::valid(q, 128));
  }
}

TEST(Tuning, TwoPointFormulaOnSeed002sReadings) {
  // Seed 002 reads t0.28 = 39 s and t0.632 = 55 s: T = 1.5·16 = 24 s as it states. The same rule
  // gives τ = 55 − 24 = 31 s; the 20.7 s the seed states does not follow from its readings.
  const tuning::Fopdt m = tuning::fopdt_from_two_points(39.0, 55.0, 45.0 / 230.0);
  EXPECT_DOUBLE_EQ(m.t_s, 24.0);
  EXPECT_DOUBLE_EQ(m.tau_s, 31.0);
  EXPECT_DOUBLE_EQ(m.k_c_per_duty, 45.0 / 230.0);
}

// Exact FOPDT step response: duty steps by du at t0 from a steady start_c.
std::vector<double> fopdt_response(const tuning::Fopdt& m, double start_c, double du, double t0,
                                   const std::vector<double>& time_s) {
  std::vector<double> y;
  for (double t : time_s) {
    const double since = t - t0 - m.tau_s;
    y.push_back(start_c + (since > 0 ? m.k_c_per_duty * du * (1 - std::exp(-since / m.t_s)) : 0.0));
  }
  return y;
}

TEST(Tuning, TwoPointFitRecoversAnFopdtFromItsStepResponse) {
  std::vector<double> t;
  for (double s = 0; s <= 400; s += 0.5) t.push_back(s);
  const std::vector<double> y = fopdt_response(kSeed002, 25.0, 0.4, 10.0, t);
  const tuning::Fopdt fit = tuning::fit_fopdt_two_point(t, y, 10.0, 0.4);
  // Interpolating between 0.5 s samples of a curve: crossings good to ~10 ms; the record ends
  // 16 time constants after the step, so the final value is exact to e^-15.
  EXPECT_NEAR(fit.k_c_per_duty, 450.0, 0.01);
  EXPECT_NEAR(fit.t_s, 24.0, 0.05);
  EXPECT_NEAR(fit.tau_s, 20.7, 0.05);
}

TEST(Tuning, TwoPointFitWorksOnACoolingStepAndSeedStyleSampling) {
  // Duty steps down by 0.2 at t = 0 (a falling response), sampled every 10 s as seed 002 did.
  std::vector<double> t;
  for (double s = 0; s <= 600; s += 10) t.push_back(s);
  const std::vector<double> y = fopdt_response(kSeed002, 210.0, -0.2, 0.0, t);
  const tuning::Fopdt fit = tuning::fit_fopdt_two_point(t, y, 0.0, -0.2);
  EXPECT_NEAR(fit.k_c_per_duty, 450.0, 0.01);
  EXPECT_NEAR(fit.t_s, 24.0, 2.0);  // 10 s sampling: straight lines across a bend
  EXPECT_NEAR(fit.tau_s, 20.7, 2.0);
}

TEST(Tuning, TwoPointFitReportsAResponseItCannotUse) {
  const std::vector<double> t{0, 10, 20, 30};
  EXPECT_EQ(tuning::fit_fopdt_two_point(t, {25, 25, 25, 25}, 0.0, 1.0).t_s, 0.0);  // no response
  EXPECT_EQ(tuning::fit_fopdt_two_point({0}, {25}, 0.0, 1.0).t_s, 0.0);            // no record
}

}  // namespace
