// The controller design's numerical building blocks: matrix exponential, ZOH with dead time,
// eigenvalues (checked against seed 000's published slow poles), modal realisation, polynomials.
#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>

#include "design/expm.h"
#include "design/poles.h"
#include "design/realization.h"
#include "design/seed_models.h"

namespace {

using namespace design;

TEST(DesignMath, ExpmOfRotationIsCosSin) {
  Mat a = zeros(2, 2);
  a(0, 1) = 1.3;
  a(1, 0) = -1.3;  // e^{A t} rotates by 1.3 t
  const Mat e = expm(2.0 * a);
  EXPECT_NEAR(e(0, 0), std::cos(2.6), 1e-13);
  EXPECT_NEAR(e(0, 1), std::sin(2.6), 1e-13);
  EXPECT_NEAR(e(1, 0), -std::sin(2.6), 1e-13);
}

TEST(DesignMath, ExpmOfLargeNormNeedsScaling) {
  Mat a = zeros(2, 2);
  a(0, 0) = -30.0;
  a(1, 1) = 5.0;
  a(0, 1) = 2.0;  // upper triangular: e^{A}_{01} = 2 (e^5 − e^-30) / 35
  const Mat e = expm(a);
  EXPECT_NEAR(e(0, 0) / std::exp(-30.0), 1.0, 1e-9);
  EXPECT_NEAR(e(1, 1) / std::exp(5.0), 1.0, 1e-12);
  EXPECT_NEAR(e(0, 1) / (2.0 * (std::exp(5.0) - std::exp(-30.0)) / 35.0), 1.0, 1e-12);
}

TEST(DesignMath, ZohOfFirstOrderMatchesClosedForm) {
  const LtiModel m = fopdt(450.0, 24.0, 0.0);
  const Zoh z = discretize(m.a, m.b, 0.768, 0.0);
  EXPECT_EQ(z.delay, 0);
  EXPECT_NEAR(z.phi(0, 0), std::exp(-0.768 / 24.0), 1e-14);
  EXPECT_NEAR(z.gamma_a(0, 0), 450.0 * (1 - std::exp(-0.768 / 24.0)), 1e-11);
  EXPECT_EQ(z.gamma_b(0, 0), 0.0);
}

// τ = D·Ts − f: the input of period k−D acts for Ts − f seconds, the next one for f seconds.
TEST(DesignMath, FractionalDelaySplitsTheInputWeight) {
  const LtiModel m = fopdt(450.0, 24.0, 20.7);
  const Zoh z = discretize(m.a, m.b, 0.768, m.delay_s);
  EXPECT_EQ(z.delay, 27);
  EXPECT_NEAR(z.frac_s, 27 * 0.768 - 20.7, 1e-12);
  const double lam = std::exp(-0.768 / 24.0);
  EXPECT_NEAR(z.gamma_a(0, 0) + z.gamma_b(0, 0), 450.0 * (1 - lam), 1e-10);
  EXPECT_NEAR(z.gamma_b(0, 0), 450.0 * (1 - std::exp(-z.frac_s / 24.0)), 1e-11);
}

TEST(DesignMath, SeedEigenvaluesMatchThePublishedSlowPoles) {
  Cplx ev[kMatCap];
  ASSERT_TRUE(eigenvalues(seed000_4_raw().a, ev));
  double slow[2] = {0, 0};
  for (int i = 0; i < 4; ++i)  // the two real ones
    if (ev[i].im == 0) (slow[0] == 0 ? slow[0] : slow[1]) = ev[i].re;
  EXPECT_NEAR(std::fmax(slow[0], slow[1]), -0.00192, 0.000005);  // README: -0.00192 / -0.00567
  EXPECT_NEAR(std::fmin(slow[0], slow[1]), -0.00567, 0.000005);
  ASSERT_TRUE(eigenvalues(seed000_5_raw().a, ev));
  double closest = 1;
  for (int i = 0; i < 5; ++i) closest = std::fmin(closest, std::fabs(ev[i].re + 0.00085));
  EXPECT_LT(closest, 0.000005);  // README: -0.00085 / -0.00981
  EXPECT_NEAR(dc_gain(seed000_4_raw()), 1.477, 0.001);
  EXPECT_NEAR(dc_gain(seed000_5_raw()), 2.225, 0.001);
  EXPECT_NEAR(dc_gain(seed000_5()), 450.0, 1e-9);
}

// The modal form must be the same system: equal step responses, y a plain sum of states.
TEST(DesignMath, ModalRealisationKeepsTheStepResponse) {
  for (const LtiModel& m : {seed000_4(), seed000_5()}) {
    Realization r;
    ASSERT_TRUE(realize(m, &r));
    EXPECT_TRUE(r.modal);
    for (int j = 0; j < m.n; ++j) EXPECT_TRUE(r.model.c(0, j) == 0.0 || r.model.c(0, j) == 1.0);
    const ExpIntegral a = exp_and_integral(m.a, m.b, 5.0);
    const ExpIntegral b = exp_and_integral(r.model.a, r.model.b, 5.0);
    Mat xa = zeros(m.n, 1), xb = zeros(m.n, 1);
    for (int k = 0; k < 200; ++k) {
      xa = a.phi * xa + a.gamma;
      xb = b.phi * xb + b.gamma;
      EXPECT_NEAR((m.c * xa)(0, 0), (r.model.c * xb)(0, 0), 1e-6 * 450) << "step " << k;
    }
  }
}

TEST(DesignMath, CharPolyOfCompanionMatrixGivesItsCoefficients) {
  const Cplx roots[4] = {{0.9, 0.1}, {0.9, -0.1}, {0.5, 0}, {-0.2, 0}};
  const Poly p = poly_from_roots(roots, 4);
  Mat comp = zeros(4, 4);  // companion matrix of p
  for (int j = 0; j < 4; ++j) comp(0, j) = -p.c[j + 1];
  for (int i = 1; i < 4; ++i) comp(i, i - 1) = 1.0;
  const Poly q = char_poly(comp);
  for (int k = 0; k <= 4; ++k) EXPECT_NEAR(q.c[k], p.c[k], 1e-14);
  EXPECT_NEAR(p.c[4], 0.82 * 0.5 * -0.2, 1e-15);  // product of roots (even degree)
}

TEST(DesignMath, ContinuousToDiscretePole) {
  const Cplx z = z_of_s({-0.25, 2.35}, 0.256);
  EXPECT_NEAR(z.re, std::exp(-0.064) * std::cos(0.6016), 1e-13);
  EXPECT_NEAR(z.im, std::exp(-0.064) * std::sin(0.6016), 1e-13);
}

TEST(DesignMath, SolveRejectsSingularMatrix) {
  Mat a = zeros(2, 2), x;
  a(0, 0) = 1;
  a(0, 1) = 2;
  a(1, 0) = 2;
  a(1, 1) = 4;
  EXPECT_FALSE(solve(a, identity(2), &x));
}

}  // namespace
