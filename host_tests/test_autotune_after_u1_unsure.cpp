// After M303 U1 on the seed000 plants, whose tunes are "unsure" (the probe's response outlasted
// the model history): host rig (host_tests/autotune_after_u1.h) at reading noise σ 0.02 °C, near
// simavr's (its 128-sample ADC window: σ ≈ 0.01–0.03 °C; the bank table's σ 0.1 reads seed000-4's
// D 33–61 s instead of simavr's 66 and is not what HIL7 meets). Noise seeds 12345, 1, 2, 3.
#include <gtest/gtest.h>

#include <cstdio>

#include "host_tests/autotune_after_u1.h"

namespace {

constexpr double kSimavrLikeNoiseC = 0.02;
const unsigned long long kSeeds[] = {12345ULL, 1ULL, 2ULL, 3ULL};

// One seed000 plant's tune, U1 and heat-up on one noise seed, printed as a table row.
struct Seed000Run {
  control::AutotuneResult tune{};
  bool statefb = false;
  after_u1::Figures figures;
};

Seed000Run tune_and_heat(const char* name, unsigned long long seed) {
  Seed000Run out;
  for (const after_u1::Plant& p : after_u1::seed000_plants())
    if (p.name == name) out.figures = after_u1::after_u1(p, seed, kSimavrLikeNoiseC, &out.tune, &out.statefb);
  const after_u1::Figures& f = out.figures;
  std::printf("%s seed %llu: C %.1f D %.1f second lag %.1f U1 %s os %.2f set %.2fx pp %.3f dip %.2f\n", name, seed,
              out.tune.model.time_constant_q8 / 256.0, out.tune.model.dead_time_q8 / 256.0,
              out.tune.second_lag_q8 / 256.0,
              out.statefb ? "statefb" : "pid+ff", f.overshoot_c, f.settling_ratio, f.steady_pp_c, f.dip_c);
  return out;
}

// seed000-4 (slow poles 521 and 176 s): the tune's record fits two lags (control/lag_fit.h),
// τ1 525–533 s and τ2 188–192 s over these seeds, and U1 designs the two-lag law on them:
// overshoot 0.01–0.02 °C, 0.95–0.97 × bound, p-p 0.03 °C, fan dip 0.09–0.18 °C. Before the fit
// the one-state law on C 965–1,037 s and D + margin 139–149 s overshot 0.0–1.4 °C, p-p 0.40–0.92,
// 1.80–1.93 × bound. Issue 7's targets after U1 (overshoot 1 °C, 1.2 × bound, p-p 0.5 °C, dip 1 °C).
TEST(AutotuneAfterU1Unsure, Seed000_4FitsTwoLagsAndMeetsTheTargets) {
  for (unsigned long long seed : kSeeds) {
    const Seed000Run r = tune_and_heat("seed000-4", seed);
    const after_u1::Figures& f = r.figures;
    EXPECT_TRUE(r.tune.unsure) << "seed " << seed;
    EXPECT_NEAR(r.tune.model.time_constant_q8 / 256.0, 521, 52) << "seed " << seed;
    EXPECT_NEAR(r.tune.second_lag_q8 / 256.0, 176, 26) << "seed " << seed;
    EXPECT_TRUE(r.statefb) << "seed " << seed;
    EXPECT_TRUE(f.ok) << "seed " << seed;
    EXPECT_LE(f.overshoot_c, 1.0) << "seed " << seed;
    EXPECT_LE(f.steady_pp_c, 0.5) << "seed " << seed;
    EXPECT_LE(f.settling_ratio, 1.2) << "seed " << seed;
    EXPECT_LE(f.dip_c, 1.0) << "seed " << seed;
  }
}

// seed000-5 (registered in HIL7) keeps the 3/8 margin (L/C ≈ 0.05): overshoot 0.00–0.73 °C,
// p-p 0.31–0.47 °C, settling 1.83–1.91 × bound; HIL7's limits, and that settling, must hold.
// Its record fits τ 1,179/118 s (plant 1,176/102), but the two-lag law on them swung 2.6 °C
// p-p (the ~20 s of dead time the fit leaves out): the tune keeps the FOPDT model (τ1 > 5 τ2).
TEST(AutotuneAfterU1Unsure, Seed000_5StaysWithinHil7) {
  for (unsigned long long seed : kSeeds) {
    const Seed000Run r = tune_and_heat("seed000-5", seed);
    const after_u1::Figures& f = r.figures;
    EXPECT_EQ(r.tune.second_lag_q8, 0) << "seed " << seed;
    EXPECT_TRUE(f.ok) << "seed " << seed;
    EXPECT_TRUE(r.statefb) << "seed " << seed;
    EXPECT_LE(f.overshoot_c, 1.0) << "seed " << seed;
    EXPECT_LE(f.steady_pp_c, 0.5) << "seed " << seed;
    EXPECT_LE(f.settling_ratio, 2.0) << "seed " << seed;
  }
}

}  // namespace
