// The state-feedback design (double precision): pole placement places the poles, M gives unit
// static gain, the predictor turns the dead-time loop into the delay-free one (delayed), the
// observer's error dynamics are the requested ones and converge, and the pole rule holds.
#include <gtest/gtest.h>

#include <cmath>

#include "design/seed_models.h"
#include "design/state_feedback_design.h"

namespace {

using namespace design;
using control::kSfMaxDelay;

struct Named {
  const char* name;
  LtiModel model;
};

const Named kPlants[] = {{"seed002", seed002()},     {"seed004", seed004()},
                         {"seed003", seed003()},     {"hotend40w", two_node()},
                         {"seed000-4", seed000_4()}, {"seed000-5", seed000_5()}};

void expect_same_poly(const Poly& got, const Poly& want, const char* what) {
  ASSERT_EQ(got.degree, want.degree);
  for (int k = 1; k <= want.degree; ++k)
    EXPECT_NEAR(got.c[k], want.c[k], 1e-7 * (1 + std::fabs(want.c[k])))
        << what << " coefficient " << k;
}

TEST(DesignStateFeedback, PolePlacementPlacesThePoles) {
  for (const Named& p : kPlants) {
    SCOPED_TRACE(p.name);
    const Design d = design_state_feedback(p.model);
    ASSERT_EQ(d.error, nullptr);
    const Mat closed = d.phi_aug - d.gamma_aug * d.l_aug;
    expect_same_poly(char_poly(closed), poly_from_roots(d.ctrl_poles_z, d.n_aug), "controller");
    const int n = d.real.model.n;
    const Mat err = d.phi_obs - d.k_obs * d.c_obs * d.phi_obs;
    expect_same_poly(char_poly(err), poly_from_roots(d.obs_poles_z, n + 1), "observer");
  }
}

TEST(DesignStateFeedback, ExplicitPolesArePlacedToo) {
  DesignOptions o;
  o.n_ctrl_poles = 2;
  o.ctrl_poles_s[0] = {-0.05, 0.02};  // a complex pair on the two-node hotend
  o.ctrl_poles_s[1] = {-0.05, -0.02};
  const Design d = design_state_feedback(two_node(), o);
  ASSERT_EQ(d.error, nullptr);
  const Poly got = char_poly(d.phi_aug - d.gamma_aug * d.l_aug);
  const Cplx z[2] = {z_of_s(o.ctrl_poles_s[0], d.ts_s), z_of_s(o.ctrl_poles_s[1], d.ts_s)};
  expect_same_poly(got, poly_from_roots(z, 2), "explicit");
}

TEST(DesignStateFeedback, FeedforwardGivesUnitStaticGain) {
  for (const Named& p : kPlants) {
    SCOPED_TRACE(p.name);
    const Design d = design_state_feedback(p.model);
    Mat c_aug = zeros(1, d.n_aug), w;
    place(&c_aug, d.real.model.c, 0, 0);
    ASSERT_TRUE(solve(identity(d.n_aug) - d.phi_aug + d.gamma_aug * d.l_aug, d.gamma_aug, &w));
    EXPECT_NEAR((c_aug * w)(0, 0) * d.m, 1.0, 1e-9);
  }
}

// Nominal loop through the real dead time with the folded predictor law vs the delay-free
// closed loop ξ⁺ = (Φ̃ − Γ̃L̃)ξ + Γ̃ M r: identical outputs, shifted by the predictor horizon.
TEST(DesignStateFeedback, PredictorMakesTheDelayedLoopTheDelayFreeOneDelayed) {
  for (const Named& p : kPlants) {
    SCOPED_TRACE(p.name);
    const Design d = design_state_feedback(p.model);
    const int n = d.real.model.n, dd = d.zoh.delay;
    const int horizon = d.zoh.frac_s > 0 ? dd - 1 : dd;
    const double r = 1.0;  // small step: no saturation in this linear check
    double x[kMatCap] = {}, hist[kSfMaxDelay + 1] = {};
    Mat w = zeros(d.n_aug, 1);
    const Mat closed = d.phi_aug - d.gamma_aug * d.l_aug;
    double y_free[4000];
    const int steps = 600 + horizon;
    for (int k = 0; k < steps; ++k) {
      y_free[k] = (d.real.model.c * block(w, 0, 0, n, 1))(0, 0);
      w = closed * w + (d.m * r) * d.gamma_aug;
      double u = d.m * r;
      for (int i = 0; i < n; ++i) u -= d.lx(0, i) * x[i];
      for (int j = 1; j <= dd; ++j) u -= d.h[j - 1] * hist[j];
      hist[0] = u;
      double y = 0;
      for (int i = 0; i < n; ++i) y += d.real.model.c(0, i) * x[i];
      if (k >= horizon) {
        ASSERT_NEAR(y, y_free[k - horizon], 1e-9) << "k = " << k;
      }
      double next[kMatCap];
      for (int i = 0; i < n; ++i) {
        next[i] =
            d.zoh.gamma_a(i, 0) * hist[dd] + d.zoh.gamma_b(i, 0) * (dd > 0 ? hist[dd - 1] : u);
        for (int j = 0; j < n; ++j) next[i] += d.zoh.phi(i, j) * x[j];
      }
      for (int i = 0; i < n; ++i) x[i] = next[i];
      for (int j = kSfMaxDelay; j >= 1; --j) hist[j] = hist[j - 1];
    }
  }
}

// Observer alone on its own model, started 50 K and 20 % duty wrong: the error must die out
// at the rate of its slowest pole.
TEST(DesignStateFeedback, ObserverConvergesFromAWrongState) {
  for (const Named& p : kPlants) {
    SCOPED_TRACE(p.name);
    const Design d = design_state_feedback(p.model);
    const int n = d.real.model.n;
    Mat err = zeros(n + 1, 1);
    for (int i = 0; i < n; ++i) err(i, 0) = 50.0 * d.ss_share(i, 0);
    err(n, 0) = 0.2;
    const Mat a = d.phi_obs - d.k_obs * d.c_obs * d.phi_obs;
    double slowest = 0;
    for (int i = 0; i <= n; ++i) slowest = std::fmax(slowest, std::sqrt(cabs2(d.obs_poles_z[i])));
    const int steps = static_cast<int>(std::log(1e-4) / std::log(slowest)) * 3;
    for (int k = 0; k < steps; ++k) err = a * err;
    double y_err = 0;
    for (int i = 0; i < n; ++i) y_err += d.real.model.c(0, i) * err(i, 0);
    EXPECT_LT(std::fabs(y_err), 50.0 * 1e-3);
    EXPECT_LT(std::fabs(err(n, 0)), 0.2 * 1e-3);
  }
}

// The rule: closed-loop time constant = full-power rise time / rf with rf from 16 down until
// saturated nominal steps (up to the design step) stay within the overshoot limit, never faster
// than 2 periods nor than twice the slowest right-half-plane zero's time constant.
TEST(DesignStateFeedback, PoleRuleLimitsOvershootUnderSaturation) {
  for (const Named& p : kPlants) {
    SCOPED_TRACE(p.name);
    const DesignOptions o;
    const Design d = design_state_feedback(p.model, o);
    ASSERT_GT(d.t_rise_s, 0.0);
    EXPECT_GE(d.t_cl_s, o.min_periods * d.ts_s - 1e-12);
    EXPECT_LE(d.t_cl_s, d.t_rise_s / 1.0);
    EXPECT_LE(worst_step_overshoot(d, o.step_k), o.overshoot_limit_k);
    if (d.rhp_zero_s > 0) {
      EXPECT_GE(d.t_cl_s, 2.0 / d.rhp_zero_s - 1e-9);
    }
  }
  // Without the search, seed 003's two slow lags brake too late and overshoot: the search matters.
  DesignOptions fixed;
  fixed.search_speed = false;
  const Design fast = design_state_feedback(seed003(), fixed);
  EXPECT_GT(worst_step_overshoot(fast, fixed.step_k), 1.0);
}

// Seed 000's identified models are non-minimum-phase (their step responses dip first): a real
// zero near +0.045/s. The cascade and two-node models have no zeros.
TEST(DesignStateFeedback, FindsTheRightHalfPlaneZeros) {
  EXPECT_NEAR(rhp_zero_limit(seed000_4()), 0.0494, 0.0005);
  EXPECT_NEAR(rhp_zero_limit(seed000_5()), 0.0452, 0.0005);
  EXPECT_EQ(rhp_zero_limit(two_node()), 0.0);
  EXPECT_EQ(rhp_zero_limit(seed003()), 0.0);
  EXPECT_EQ(rhp_zero_limit(seed002()), 0.0);
}

TEST(DesignStateFeedback, DeadTimeFitsTheHistoryByDecimation) {
  const Design d = design_state_feedback(seed002());  // τ = 20.7 s
  EXPECT_LE(d.zoh.delay, kSfMaxDelay);
  EXPECT_GE(d.decimation,
            control::state_feedback_min_decimation(static_cast<uint8_t>(d.zoh.delay)));
  EXPECT_NEAR(d.zoh.delay * d.ts_s - d.zoh.frac_s, 20.7, 1e-9);
  EXPECT_EQ(design_state_feedback(two_node()).zoh.delay, 0);
}

}  // namespace
