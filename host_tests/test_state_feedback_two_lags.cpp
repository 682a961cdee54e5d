// control/state_feedback_autodesign's two-lag design (n = 2, integer-only) against the host's
// double-precision design of the same model, design::second_order(K, τ1 = C, τ2 = D) with the
// board's closed-loop speed (T_cl = max(t_rise/16, κ·τ2, 2h) instead of the host's saturation
// search): constants field by field, and both closed loops on the exact two-lag plant.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "control/state_feedback.h"
#include "control/state_feedback_autodesign.h"
#include "design/plant_sim.h"
#include "design/state_feedback_quantize.h"
#include "host_tests/autodesign_compare.h"

namespace {

using control::HotendModel;
using control::StateFeedbackConstants;
using autodesign_compare::closed_loop;
using autodesign_compare::Field;
using autodesign_compare::fields;
using autodesign_compare::value;

struct TwoLags {
  double k, t1, t2, f;  // °C per unit duty, s, s, % of the no-fan loss
};

HotendModel board_model(const TwoLags& p) {
  return HotendModel{static_cast<int32_t>(std::lround(p.k * 256)), static_cast<int32_t>(std::lround(p.t1 * 256)),
                     static_cast<int32_t>(std::lround(p.t2 * 256)), static_cast<int32_t>(std::lround(p.f * 256))};
}

design::LtiModel host_model(const HotendModel& m) {
  const double k = m.rise_q8 / 256.0;
  design::LtiModel model = design::second_order(k, m.time_constant_q8 / 256.0, m.dead_time_q8 / 256.0);
  model.fan_loss_per_k = m.fan_loss_pct_q8 / 256.0 / 100.0 / k;
  return model;
}

// The board's pole rule in double (state_feedback_autodesign.h), then the host's design at it.
// T_cl ≥ κ·τ2, κ = pace_tenths/10.
design::Design host_design(const HotendModel& m, uint8_t pace_tenths) {
  const double k = m.rise_q8 / 256.0, t1 = m.time_constant_q8 / 256.0, t2 = m.dead_time_q8 / 256.0, h = 0.256;
  const double t_rise = k > 185 ? t1 * std::log(k * t1 / (t1 - t2) / (k - 185)) : t1;
  const double c = std::fmin(std::fmin(16 * h / t_rise, h / (pace_tenths / 10.0 * t2)), 0.5);
  const design::LtiModel model = host_model(m);
  design::DesignOptions o;
  design::Design probe;
  design::design_model(model, o, &probe);
  o.search_speed = false;
  o.rise_fraction = (probe.t_rise_s > 0 ? probe.t_rise_s : probe.t_dom_s) / (h / c);
  return design::design_state_feedback(model, o);
}

// K 300–1200 °C, τ1 20–400 s, τ2 1.2–45 % of τ1 (at least 0.5 s), F 0–60 %. The small ratios are
// the two-node hotends' (hotend40w/80w: a 4.5 s lag on C ≈ 245 s; light-fast 1 s on 88 s), which
// U1 also serves with two lags.
std::vector<TwoLags> grid() {
  const double ks[] = {300, 450, 700, 1200}, ts[] = {20, 45, 100, 220, 400},
               rs[] = {0.012, 0.02, 0.06, 0.12, 0.25, 0.45};
  const double fs[] = {0, 25, 42.65, 60};
  std::vector<TwoLags> out;
  int i = 0;
  for (double k : ks)
    for (double t : ts)
      for (double r : rs) out.push_back(TwoLags{k, t, std::fmax(0.5, r * t), fs[i++ % 4]});
  return out;
}

void expect_matches_host_field_by_field(uint8_t pace_tenths) {
  double worst_rel = 0;
  int worst_lsb = 0, shift_mismatches = 0;
  std::string worst_rel_field, worst_lsb_field;
  for (const TwoLags& p : grid()) {
    SCOPED_TRACE(::testing::Message() << "K " << p.k << " t1 " << p.t1 << " t2 " << p.t2 << " F " << p.f);
    const HotendModel m = board_model(p);
    StateFeedbackConstants board, host;
    ASSERT_TRUE(control::design_state_feedback_two_lags(m, 128, &board, pace_tenths));
    const design::Design d = host_design(m, pace_tenths);
    ASSERT_EQ(d.error, nullptr);
    const char* err = design::quantize(d, host_model(m).fan_loss_per_k, &host);
    ASSERT_EQ(err, nullptr) << err;
    control::StateFeedback sf;
    EXPECT_TRUE(sf.configure(board));
    EXPECT_EQ(board.n, host.n);
    EXPECT_EQ(board.output_mask, host.output_mask);
    EXPECT_EQ(board.delay, host.delay);
    EXPECT_EQ(board.decimation, host.decimation);
    EXPECT_EQ(board.input_shift, host.input_shift);
    EXPECT_EQ(board.ambient_q8, host.ambient_q8);
    EXPECT_EQ(board.phi_col[0], host.phi_col[0]);
    EXPECT_EQ(board.phi_col[1], host.phi_col[1]);
    for (const Field& f : fields(board, host)) {
      SCOPED_TRACE(f.name);
      const double vb = value(f.mb, f.sb), vh = value(f.mh, f.sh);
      const double rel = vh != 0 ? std::fabs(vb - vh) / std::fabs(vh) : std::fabs(vb);
      if (f.sb != f.sh) {
        ++shift_mismatches;
        EXPECT_LT(rel, 1e-4);
      } else {
        const int lsb = std::abs(f.mb - f.mh);
        EXPECT_LE(lsb, 2);
        if (lsb > worst_lsb) worst_lsb = lsb, worst_lsb_field = f.name;
      }
      if (rel > worst_rel) worst_rel = rel, worst_rel_field = f.name;
    }
  }
  std::printf("two-lag design (pace %.1f), on-board vs host, %zu models: worst relative %.2e (%s), worst %d LSB (%s), "
              "rows at a different shift %d\n",
              pace_tenths / 10.0, grid().size(), worst_rel, worst_rel_field.c_str(), worst_lsb, worst_lsb_field.c_str(), shift_mismatches);
}

// Lags the relay confirmed (κ 0.4).
TEST(StateFeedbackTwoLags, MatchesTheHostDesignFieldByField) {
  expect_matches_host_field_by_field(control::kLagPaceConfirmed);
}

// Other lags (κ 0.6), and fitted ones with τ2 < τ1/5 (κ 1.2): control/autotune_design.h.
TEST(StateFeedbackTwoLags, SlowerPacesMatchTheHostDesignFieldByField) {
  expect_matches_host_field_by_field(control::kLagPaceDefault);
  expect_matches_host_field_by_field(control::kLagPaceWide);
}

// At κ 0.4 (a confirmed lag) and 0.6 (other lags).
TEST(StateFeedbackTwoLags, ClosedLoopFollowsTheHostDesignWithinTwoTenthsOfAKelvin) {
  double worst = 0;
  TwoLags worst_at{};
  for (const uint8_t pace : {control::kLagPaceConfirmed, control::kLagPaceDefault})
  for (const TwoLags& p : grid()) {
    const HotendModel m = board_model(p);
    const design::LtiModel plant = host_model(m);
    StateFeedbackConstants board, host;
    ASSERT_TRUE(control::design_state_feedback_two_lags(m, 128, &board, pace));
    ASSERT_EQ(design::quantize(host_design(m, pace), plant.fan_loss_per_k, &host), nullptr);
    const double rise_s = -p.t1 * std::log(1 - 185 / p.k) + p.t2;
    const double fan_at = 2 * rise_s + 4 * p.t2 + 30;
    const std::vector<double> a = closed_loop(plant, board, fan_at, fan_at + 0.5 * p.t1 + 4 * p.t2 + 30);
    const std::vector<double> b = closed_loop(plant, host, fan_at, fan_at + 0.5 * p.t1 + 4 * p.t2 + 30);
    const size_t before_fan = static_cast<size_t>(fan_at / 0.128) - 1;
    EXPECT_NEAR(a[before_fan], 210, 0.3) << "K " << p.k << " t1 " << p.t1 << " t2 " << p.t2;
    EXPECT_NEAR(a.back(), 210, 0.5) << "K " << p.k << " t1 " << p.t1 << " t2 " << p.t2;
    double dev = 0;
    for (size_t i = 0; i < a.size(); ++i) dev = std::fmax(dev, std::fabs(a[i] - b[i]));
    EXPECT_LE(dev, 0.2) << "K " << p.k << " t1 " << p.t1 << " t2 " << p.t2 << " F " << p.f;
    if (dev > worst) worst = dev, worst_at = p;
  }
  std::printf("two-lag closed loop, on-board vs host constants: worst |dT| %.4f °C at K %g t1 %g t2 %g F %g\n", worst,
              worst_at.k, worst_at.t1, worst_at.t2, worst_at.f);
}

// Outside what it designs: all-zero constants no controller accepts.
TEST(StateFeedbackTwoLags, RefusesModelsItDoesNotDesign) {
  const HotendModel good = board_model(TwoLags{460, 43, 12, 30});
  const HotendModel bad[] = {
      {good.rise_q8, good.time_constant_q8, 0, good.fan_loss_pct_q8},                          // no second lag
      {good.rise_q8, good.time_constant_q8, good.time_constant_q8 / 2 + 1, good.fan_loss_pct_q8},  // τ2 > τ1/2
      {0, good.time_constant_q8, good.dead_time_q8, good.fan_loss_pct_q8},
      {INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX},
  };
  const StateFeedbackConstants zero = {};
  for (const HotendModel& m : bad) {
    StateFeedbackConstants k;
    std::memset(&k, 0x5A, sizeof k);
    EXPECT_FALSE(control::design_state_feedback_two_lags(m, 128, &k, control::kLagPaceConfirmed));
    EXPECT_EQ(std::memcmp(&k, &zero, sizeof k), 0);
  }
  StateFeedbackConstants k;
  EXPECT_TRUE(control::design_state_feedback_two_lags(good, 128, &k, control::kLagPaceConfirmed));
  EXPECT_FALSE(control::design_state_feedback_two_lags(good, 0, &k, control::kLagPaceConfirmed));
  EXPECT_FALSE(control::design_state_feedback_two_lags(good, 128, &k, 0));
}

// The corners of what M307 accepts read as two lags: every design passes the runtime's checks
// (and the controller takes it) or is refused with all-zero constants; none crashes.
TEST(StateFeedbackTwoLags, EdgeModelsAreValidOrRefused) {
  const double ks[] = {10, 100, 185, 190, 2000}, ts[] = {1, 3, 30, 600, 3600}, rs[] = {0.01, 0.1, 0.25, 0.5};
  int designed = 0, total = 0;
  const StateFeedbackConstants zero = {};
  for (double kk : ks)
    for (double t : ts)
      for (double r : rs) {
        SCOPED_TRACE(::testing::Message() << "K " << kk << " t1 " << t << " t2 " << r * t);
        ++total;
        StateFeedbackConstants k;
        if (!control::design_state_feedback_two_lags(board_model(TwoLags{kk, t, r * t, 500}), 128, &k, control::kLagPaceConfirmed)) {
          EXPECT_EQ(std::memcmp(&k, &zero, sizeof k), 0);
          continue;
        }
        ++designed;
        EXPECT_TRUE(control::state_feedback_constants_valid(k));
        control::StateFeedback sf;
        EXPECT_TRUE(sf.configure(k));
      }
  std::printf("two-lag edge models designed: %d of %d\n", designed, total);
  EXPECT_GT(designed, total / 2);
}

}  // namespace
