// control/lag_fit.h against the double-precision least squares on the same samples, and both
// against the plant: two lags in cascade (and an underdamped pair, which has no two real lags),
// driven from rest by a heat-up at full power and then a relay-like square wave, sampled once a
// bin as the tune samples: ∫u, y and ∫y through a 16-bin first-order filter, ẏ the filtered y's
// change per bin (control/autotune.cpp, fit_bin).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "control/lag_fit.h"

namespace {

constexpr double kBinS = 1.024;  // the tune's bin: 8 periods of 128 ms
constexpr uint16_t kBinMs = 1024;

struct Fit {
  double k = 0, tau1 = 0, tau2 = 0;
  bool ok = false;
};

// y'' + a1·y' + a0·y = b0·u, run from rest with the bin's duty held; one sample per bin.
struct Record {
  std::vector<double> iu, y, slope, iy;
};

Record simulate(double a1, double a0, double b0, int bins) {
  Record r;
  double x = 0, v = 0, iu = 0, iy = 0, fu = 0, fy = 0, fiy = 0;
  for (int n = 0; n < bins; ++n) {
    // Full power until 120 °C of rise (at least 100 bins, at most 400), then a square wave
    // between 10 and 50 % every 200 bins.
    const double u = n < 100 || (x < 120 && n < 400) ? 1.0 : ((n / 200) % 2 ? 0.5 : 0.1);
    constexpr int kSub = 64;
    for (int s = 0; s < kSub; ++s) {
      const double dt = kBinS / kSub;
      const double acc = b0 * u - a1 * v - a0 * x;
      v += acc * dt;
      x += v * dt;
    }
    iu += u;
    iy += x;
    fu += (iu - fu) / 16;
    fiy += (iy - fiy) / 16;
    const double dy = (x - fy) / 16;
    fy += dy;
    if (x < 30) continue;
    r.iu.push_back(fu);
    r.y.push_back(fy);
    r.slope.push_back(dy);
    r.iy.push_back(fiy);
  }
  return r;
}

Fit to_fit(double k, double sigma, double pi) {
  Fit f;
  const double d = sigma * sigma - 4 * pi;
  if (sigma <= 0 || pi <= 0 || d <= 0) return f;
  f.k = k;
  f.tau1 = (sigma + std::sqrt(d)) / 2 * kBinS;
  f.tau2 = pi / ((sigma + std::sqrt(d)) / 2) * kBinS;
  f.ok = true;
  return f;
}

// The double reference: normal equations for ∫y = K·∫u − Σ·y − Π·ẏ, solved by Cramer's rule.
Fit fit_double(const Record& r) {
  double m[3][3] = {}, v[3] = {};
  for (std::size_t i = 0; i < r.y.size(); ++i) {
    const double x[3] = {r.iu[i], r.y[i], r.slope[i]};
    for (int a = 0; a < 3; ++a) {
      v[a] += x[a] * r.iy[i];
      for (int b = 0; b < 3; ++b) m[a][b] += x[a] * x[b];
    }
  }
  auto det = [](double q[3][3]) {
    return q[0][0] * (q[1][1] * q[2][2] - q[1][2] * q[2][1]) - q[0][1] * (q[1][0] * q[2][2] - q[1][2] * q[2][0]) +
           q[0][2] * (q[1][0] * q[2][1] - q[1][1] * q[2][0]);
  };
  const double d = det(m);
  double x[3];
  for (int c = 0; c < 3; ++c) {
    double q[3][3];
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) q[a][b] = b == c ? v[a] : m[a][b];
    x[c] = det(q) / d;
  }
  return to_fit(x[0], -x[1], -x[2]);
}

// The board's: every sample through lag_fit_accumulate's pieces, then lag_fit_solve's.
Fit fit_board(const Record& r, int* pieces = nullptr) {
  fixed_math::Scaled m[control::kLagFitSums] = {};
  int n = 0;
  for (std::size_t i = 0; i < r.y.size(); ++i) {
    // lag_fit_accumulate's scales: ∫u, y × 2^12, ẏ × 2^16, ∫y × 2^8.
    const int32_t x[4] = {static_cast<int32_t>(std::lround(r.iu[i] * 4096)), static_cast<int32_t>(std::lround(r.y[i] * 4096)),
                          static_cast<int32_t>(std::lround(r.slope[i] * 65536)), static_cast<int32_t>(std::lround(r.iy[i] * 256))};
    for (uint8_t s = 1; s != 0; s = control::lag_fit_accumulate(m, x, s)) ++n;
  }
  int32_t out[4] = {};
  for (uint8_t s = 1; s != 0; s = control::lag_fit_solve(m, kBinMs, out, s)) ++n;
  if (pieces) *pieces = n;
  Fit f;
  if (out[1] == 0) return f;
  f.k = out[0] / 256.0;
  f.tau1 = out[1] / 256.0;
  f.tau2 = out[2] / 256.0;
  f.ok = true;
  return f;
}

double rel(double a, double b) { return std::fabs(a - b) / std::fabs(b); }

TEST(LagFit, BoardMatchesTheDoubleLeastSquaresAndFindsTheLags) {
  struct Case {
    double k, tau1, tau2;  // s
  };
  // seed000-4's slow poles (521, 176 s), seed000-5's (1,176, 102), a mid pair and a fast one.
  const Case cases[] = {{450, 521, 176}, {450, 1176, 102}, {300, 300, 60}, {450, 50, 10}, {250, 200, 100}};
  double worst_board = 0, worst_truth = 0;
  for (const Case& c : cases) {
    const double t1 = c.tau1 / kBinS, t2 = c.tau2 / kBinS;  // in bins
    const Record r = simulate((t1 + t2) / (t1 * t2), 1 / (t1 * t2), c.k / (t1 * t2), 2500);
    const Fit d = fit_double(r), b = fit_board(r);
    ASSERT_TRUE(d.ok && b.ok) << c.tau1 << "/" << c.tau2;
    const double eb = std::max({rel(b.k, d.k), rel(b.tau1, d.tau1), rel(b.tau2, d.tau2)});
    const double et = std::max({rel(b.k, c.k), rel(b.tau1, c.tau1), rel(b.tau2, c.tau2)});
    std::printf("τ %.0f/%.0f s: double K %.2f τ %.2f/%.2f, board K %.2f τ %.2f/%.2f (board−double %.2e, −plant %.2f %%)\n",
                c.tau1, c.tau2, d.k, d.tau1, d.tau2, b.k, b.tau1, b.tau2, eb, 100 * et);
    worst_board = std::max(worst_board, eb);
    worst_truth = std::max(worst_truth, et);
    // Inputs rounded to their scales and 29-bit Scaled arithmetic: measured ≤ 7.6e-5.
    EXPECT_LT(eb, 2e-4) << c.tau1 << "/" << c.tau2;
    // The bin-sampled equation against the continuous plant: τ1 reads 2.4–3.7 % short here.
    EXPECT_LT(et, 0.05) << c.tau1 << "/" << c.tau2;
  }
  std::printf("worst relative error: board against double %.2e, against the plant %.2f %%\n", worst_board,
              100 * worst_truth);
}

// An underdamped pair (ζ 0.5) has no two real lags: Σ² < 4Π, and the board says so (τ1 = 0).
TEST(LagFit, AnUnderdampedPairIsNoFit) {
  const double w = 1.0 / 100;  // rad per bin
  const Record r = simulate(2 * 0.5 * w, w * w, 450 * w * w, 2500);
  EXPECT_FALSE(fit_double(r).ok);
  EXPECT_FALSE(fit_board(r).ok);
}

// The pieces: 36 per sample and 42 for the solution (the tune spreads them over idle steps).
TEST(LagFit, PieceCounts) {
  const double t1 = 521 / kBinS, t2 = 176 / kBinS;
  const Record r = simulate((t1 + t2) / (t1 * t2), 1 / (t1 * t2), 450 / (t1 * t2), 600);
  int pieces = 0;
  ASSERT_TRUE(fit_board(r, &pieces).ok);
  EXPECT_EQ(pieces, 36 * static_cast<int>(r.y.size()) + 42);
}

}  // namespace
