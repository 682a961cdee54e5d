// After M303 U1 on the seed000 plants, whose tunes are "unsure" (the probe's response outlasted
// the model history): host rig (host_tests/autotune_after_u1.h) at reading noise σ 0.02 °C, near
// simavr's (its 128-sample ADC window: σ ≈ 0.01–0.03 °C; the bank table's σ 0.1 reads seed000-4's
// D 33–61 s instead of simavr's 66 and is not what HIL7 meets). Noise seeds 12345, 1, 2, 3.
#include <gtest/gtest.h>

#include <cmath>
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
  std::printf("%s seed %llu: C %.1f D %.1f lags %.1f %.1f U1 %s os %.2f set %.2fx pp %.3f dip %.2f\n", name, seed,
              out.tune.model.time_constant_q8 / 256.0, out.tune.model.dead_time_q8 / 256.0,
              out.tune.first_lag_q8 / 256.0, out.tune.second_lag_q8 / 256.0,
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
    EXPECT_NEAR(r.tune.first_lag_q8 / 256.0, 521, 52) << "seed " << seed;
    EXPECT_NEAR(r.tune.second_lag_q8 / 256.0, 176, 26) << "seed " << seed;
    EXPECT_TRUE(r.statefb) << "seed " << seed;
    EXPECT_TRUE(f.ok) << "seed " << seed;
    EXPECT_LE(f.overshoot_c, 1.0) << "seed " << seed;
    EXPECT_LE(f.steady_pp_c, 0.5) << "seed " << seed;
    EXPECT_LE(f.settling_ratio, 1.2) << "seed " << seed;
    EXPECT_LE(f.dip_c, 1.0) << "seed " << seed;
  }
}

// seed000-5 (registered in HIL7): its record fits τ 1,168–1,181 / 121–122 s (plant 1,176/102),
// τ2 < τ1/5: M307 becomes their two-point FOPDT and the state feedback the paced two-lag law
// (T_cl ≥ 1.2·τ2): overshoot 0.03–0.05 °C, p-p 0.05–0.08 °C, 1.54–1.56 × bound, fan dip
// 0.71–0.96 °C. Before, the one-state law on the relay's C and D + 3/8: 0.00–0.73 °C, p-p
// 0.31–0.47 °C, 1.83–1.91 ×. Issue 7's 1.2 × is still missed.
TEST(AutotuneAfterU1Unsure, Seed000_5StaysWithinHil7) {
  for (unsigned long long seed : kSeeds) {
    const Seed000Run r = tune_and_heat("seed000-5", seed);
    const after_u1::Figures& f = r.figures;
    EXPECT_NEAR(r.tune.first_lag_q8 / 256.0, 1176, 118) << "seed " << seed;
    EXPECT_NEAR(r.tune.second_lag_q8 / 256.0, 102, 26) << "seed " << seed;
    EXPECT_LT(5 * r.tune.second_lag_q8, r.tune.first_lag_q8) << "seed " << seed;
    EXPECT_TRUE(f.ok) << "seed " << seed;
    EXPECT_TRUE(r.statefb) << "seed " << seed;
    EXPECT_LE(f.overshoot_c, 1.0) << "seed " << seed;
    EXPECT_LE(f.steady_pp_c, 0.5) << "seed " << seed;
    EXPECT_LE(f.settling_ratio, 1.7) << "seed " << seed;
    EXPECT_LE(f.dip_c, 1.0) << "seed " << seed;
  }
}

// The PID family on the settings the tune computed (M310 S0/S2, F0/F1 after U1), seed000 plants:
// HIL3's heat-up limits (overshoot ≤ 3 °C, |steady mean| ≤ 0.5 °C, p-p ≤ 1 °C before the fan
// step). M307 from the fitted lags' two-point FOPDT (lag-type: fuzzy-PID F0 follows its heat-up)
// put them there: host rig, fuzzy-PID −0.09 to −0.24 °C mean, ≤ 1.2 °C of overshoot; seed000-5's
// PID −0.05 to 0.23 °C (before: −0.7 to −23 °C means, 17–23 °C overshoots). seed000-4's PID since
// the tight PI on fitted lags and PID F0's model heat-up on a lag-type model: −0.19 to −0.40 °C
// (before −0.41 to −0.50 °C here, −0.52 / −0.72 °C in simavr; docs/autotune.md, "The PID family
// on seed000").
TEST(AutotuneAfterU1Unsure, PidFamilyOnTheTunedSettingsHeatsWithinHil3) {
  struct Choice {
    const char* plant;
    firmware::ControllerId id;
    uint8_t feedforward;
  };
  const Choice choices[] = {{"seed000-4", firmware::ControllerId::kFuzzyPid, 0},
                            {"seed000-4", firmware::ControllerId::kFuzzyPid, 1},
                            {"seed000-4", firmware::ControllerId::kPid, 0},
                            {"seed000-4", firmware::ControllerId::kPid, 1},
                            {"seed000-5", firmware::ControllerId::kFuzzyPid, 0},
                            {"seed000-5", firmware::ControllerId::kFuzzyPid, 1},
                            {"seed000-5", firmware::ControllerId::kPid, 0},
                            {"seed000-5", firmware::ControllerId::kPid, 1}};
  for (const after_u1::Plant& p : after_u1::seed000_plants()) {
    for (unsigned long long seed : kSeeds) {
      control::AutotuneResult r{};
      ASSERT_TRUE(after_u1::tune(p, seed, kSimavrLikeNoiseC, &r)) << p.name << " seed " << seed;
      control::TunedDesign d;
      ASSERT_TRUE(control::design_from_tune(r, firmware::kControlPeriodMs, &d));
      EXPECT_EQ(firmware::tuned_model_source(r), firmware::kModelFittedLags) << p.name;
      for (const Choice& c : choices) {
        if (p.name != c.plant) continue;
        after_u1::Applied a = after_u1::applied(r, d, false);
        a.settings.controller = static_cast<uint8_t>(c.id);
        a.settings.feedforward = c.feedforward;
        const after_u1::Figures f = after_u1::run(p, a);
        std::printf("%s seed %llu M310 S%u F%u: os %.2f set %.2fx mean %.2f pp %.2f dip %.2f\n", c.plant, seed,
                    static_cast<unsigned>(c.id), static_cast<unsigned>(c.feedforward), f.overshoot_c, f.settling_ratio,
                    f.steady_mean_c, f.steady_pp_c, f.dip_c);
        EXPECT_LE(f.overshoot_c, 3.0) << c.plant << " S" << int(c.id) << " F" << int(c.feedforward) << " seed " << seed;
        EXPECT_LE(std::fabs(f.steady_mean_c), 0.5) << c.plant << " S" << int(c.id) << " F" << int(c.feedforward);
        EXPECT_LE(f.steady_pp_c, 1.0) << c.plant << " S" << int(c.id) << " F" << int(c.feedforward);
      }
    }
  }
}

}  // namespace
