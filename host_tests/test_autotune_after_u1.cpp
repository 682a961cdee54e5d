// After M303 U1 on the plant bank (host rig: host_tests/autotune_after_u1.h): the fixed-point
// tune, the board's design and the firmware's controllers on double-precision plants, heat-up
// from ambient and a part-fan step. Issue 7's targets after U1: overshoot ≤ 1 °C, settling ≤ 1.2 ×
// the physical bound, steady p-p ≤ 0.5 °C, fan-step dip ≤ 1 °C. The rig has no ADC, so its figures
// differ from simavr's (docs/bench/README.md) by a few hundredths to tenths.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>

#include "design/state_feedback_quantize.h"
#include "host_tests/autotune_after_u1.h"

namespace {

using after_u1::Figures;

struct Limits {
  double overshoot_c, settling_ratio;
};

// Issue 7's targets, or (misses, measured at this commit on noise seed 12345, σ 0.1 °C) a
// ceiling a little above the figure so that a worse design fails. None now: heavy-slow and
// seed003 (one-state design: 1.69 × and 2.13 ×) meet the targets with the two-lag design
// (1.01 ×, 0.89 ×), and so does hotend80w, which missed them with the paced one-state law
// (1.58 °C, 1.25 ×).
const std::map<std::string, Limits> kMisses = {};

TEST(AutotuneAfterU1, EveryPlantMeetsTheTargetsOrItsKnownMiss) {
  std::printf("%-17s %-7s %8s %8s %7s %6s %8s\n", "plant", "U1", "os °C", "set ×", "p-p °C", "dip °C", "D s");
  for (const after_u1::Plant& p : after_u1::plants()) {
    control::AutotuneResult r{};
    bool sf = false;
    const Figures f = after_u1::after_u1(p, 12345, 0.1, &r, &sf);
    control::TunedDesign d;
    ASSERT_TRUE(control::design_from_tune(r, firmware::kControlPeriodMs, &d)) << p.name;
    std::printf("%-17s %-7s %8.2f %8.2f %7.3f %6.2f %8.2f\n", p.name.c_str(), sf ? "statefb" : "pid+ff", f.overshoot_c,
                f.settling_ratio, f.steady_pp_c, f.dip_c, d.model.dead_time_q8 / 256.0);
    const auto miss = kMisses.find(p.name);
    const Limits lim = miss == kMisses.end() ? Limits{1.0, 1.2} : miss->second;
    EXPECT_TRUE(f.ok) << p.name;
    EXPECT_LE(f.overshoot_c, lim.overshoot_c) << p.name;
    EXPECT_LE(f.settling_ratio, lim.settling_ratio) << p.name;
    EXPECT_LE(f.steady_pp_c, 0.5) << p.name;
    EXPECT_LE(f.dip_c, 1.0) << p.name;
  }
}

// The hot starts' modes by name (AUTOTUNE_HELD_MODE, AUTOTUNE_HELD_MODES).
after_u1::HotStart hot_start_mode(const std::string& name) {
  return name == "unheld" ? after_u1::HotStart::kUnheld
         : name == "m109" ? after_u1::HotStart::kAfterM109
                          : after_u1::HotStart::kHeld;
}

// After a hot start (M303 at S after printing at S − 10 long enough for the steady hold): the
// same heat-up from ambient and fan step with what U1 applied, and the model. AUTOTUNE_HELD_FROM=
// <°C from the target> starts elsewhere (−10; "cold": from ambient, for comparison),
// AUTOTUNE_HELD_SEED=n takes another noise realisation, AUTOTUNE_HELD_MODE=unheld|m109 another way
// of getting there (after_u1::HotStart).
TEST(AutotuneAfterU1, HeldHotStartTable) {
  const char* from_env = std::getenv("AUTOTUNE_HELD_FROM");
  const bool cold = from_env != nullptr && std::string(from_env) == "cold";
  const double from = from_env != nullptr ? std::atof(from_env) : -10.0;
  const char* seed_env = std::getenv("AUTOTUNE_HELD_SEED");
  const unsigned long long seed = seed_env != nullptr ? std::strtoull(seed_env, nullptr, 10) : 12345;
  const char* mode_env = std::getenv("AUTOTUNE_HELD_MODE");
  const after_u1::HotStart how = hot_start_mode(mode_env ? mode_env : "held");
  // AUTOTUNE_HELD_SEED000=1: seed000-4 and seed000-5 instead (slow: 150 °C, 2,400 s runs).
  const std::vector<after_u1::Plant> ps =
      std::getenv("AUTOTUNE_HELD_SEED000") != nullptr ? after_u1::seed000_plants() : after_u1::plants();
  std::printf("%-17s %-7s %8s %8s %7s %6s | %7s %7s %6s %6s %6s %6s\n", "plant", "U1", "os °C", "set ×", "p-p °C", "dip °C",
              "A", "C s", "D s", "Ku", "Tu s", "F %");
  for (const after_u1::Plant& p : ps) {
    control::AutotuneResult r{};
    bool sf = false;
    const Figures f = after_u1::after_u1(p, seed, 0.1, &r, &sf, cold ? 0.0 : p.target_c + from, how);
    std::printf("%-17s %-7s %8.2f %8.2f %7.3f %6.2f | %7.1f %7.1f %6.2f %6.2f %6.2f %6.2f%s\n", p.name.c_str(),
                sf ? "statefb" : "pid+ff", f.overshoot_c, f.settling_ratio, f.steady_pp_c, f.dip_c,
                r.model.rise_q8 / 256.0, r.model.time_constant_q8 / 256.0, r.model.dead_time_q8 / 256.0,
                r.ultimate.ku_q8 / 256.0, r.ultimate.tu_q8 / 256.0, r.model.fan_loss_pct_q8 / 256.0, f.ok ? "" : " FAIL");
  }
}

struct HotLimits {
  double overshoot_c, settling_ratio, dip_c;
};

// After a hot start, held (SteadyHold's K) or unheld at S − 60, S − 30, S − 10 and S + 20 °C, or
// right after `M109` at S − 100, −60, −30, −10 (after_u1::HotStart), what U1 applies meets issue
// 7's targets on every plant whose tune finishes, or its known miss (kHotMisses). Before the
// cool-down's T and the relay's lag (docs/autotune.md, "A hot start's time constant from its
// cool-down"), 96 of these 128 runs missed a target (now 17): seed002 overshot 8.8–14 °C,
// seed004 7–11, seed003 8–12, fopdt-120-25 up to 13, hotend80w 2–5, heavy-slow up to 6 (2.7 × bound).
// Tunes that end without a result are the tune tables' business (host_tests/test_autotune.cpp;
// after M109 seed002 and seed004 abort on the default PID's own overshoot): counted and bounded.
// AUTOTUNE_HELD_SWEEP="−60,−45,…" (°C from the target, every mode), AUTOTUNE_HELD_MODES=
// "held,unheld,m109", AUTOTUNE_HELD_SEEDS=n (12345, 1, 2, …) and AUTOTUNE_HELD_NOISE=σ widen it
// into a diagnostic sweep (its limits still asserted).
const std::map<std::string, HotLimits> kHotMisses = {
    // A 5 s transport delay before the lag: every T a hot start reads is off (held: decay 270–297
    // s, loss ~300, relay 375 for 245.6; after M109: 220–230), so U1 heats slowly (1.26–1.49 ×
    // bound) or, from S and S + 20 held or after M109, overshoots 1.1–3.7 °C.
    {"hotend40w-delay5", {3.8, 1.55, 1.0}},
    // From S − 30 (held, unheld) and S − 10 (unheld, after M109) the approach's loss read a long
    // T and its S half the other starts': F 60–98 %, C 71–83 s; 3.1–5.5 °C over.
    {"seed003", {5.6, 1.2, 1.0}},
    // Unheld, the relay's K and a loss-read C of 472–508 s (285.7): 1.24–1.26 × bound, dip 1.09.
    {"heavy-slow", {1.0, 1.3, 1.2}},
    // After M109 from S − 60: 1.47 × bound (C 118.4, D 25.1: the model is right; the heat-up's
    // PID following it lands slowly).
    {"fopdt-delay25", {1.0, 1.5, 1.0}},
};
constexpr int kHotUnfinished = 16;  // held 1, unheld 2, after M109 13 (seed002, seed004: 4 each)
constexpr int kHotUnsure = 1;  // heavy-slow after M109 from S − 100 (its relay's figures: 6.3 °C over, as before)

TEST(AutotuneAfterU1, AfterAHotStartEveryPlantMeetsTheTargetsOrItsKnownMiss) {
  struct Mode {
    std::string name;
    std::vector<double> froms;
  };
  std::vector<Mode> modes = {{"held", {-60, -30, -10, 20}}, {"unheld", {-60, -30, -10, 20}},
                             {"m109", {-100, -60, -30, -10}}};
  const char* sweep_env = std::getenv("AUTOTUNE_HELD_SWEEP");
  if (sweep_env != nullptr) {
    std::vector<double> froms;
    std::istringstream fs(sweep_env);
    std::string tok;
    while (std::getline(fs, tok, ',')) froms.push_back(std::atof(tok.c_str()));
    for (Mode& m : modes) m.froms = froms;
  }
  const char* modes_env = std::getenv("AUTOTUNE_HELD_MODES");
  if (modes_env != nullptr) {
    std::vector<Mode> chosen;
    for (const Mode& m : modes)
      if (std::string(modes_env).find(m.name) != std::string::npos) chosen.push_back(m);
    modes = chosen;
  }
  const char* seeds_env = std::getenv("AUTOTUNE_HELD_SEEDS");
  const int n_seeds = seeds_env ? std::atoi(seeds_env) : 1;
  const char* noise_env = std::getenv("AUTOTUNE_HELD_NOISE");
  const double noise = noise_env ? std::atof(noise_env) : 0.1;
  int unfinished_all = 0, over_all = 0, runs_all = 0, unsure = 0;
  for (const Mode& mode : modes) {
    std::printf("%s\n%-17s %5s %5s | %8s %8s %7s %6s | %s\n", mode.name.c_str(), "plant", "runs", "unfin", "os °C",
                "set ×", "p-p °C", "dip °C", "largest overshoot (from, seed)");
    for (const after_u1::Plant& p : after_u1::plants()) {
      const auto miss = kHotMisses.find(p.name);
      const HotLimits lim = miss == kHotMisses.end() ? HotLimits{1.0, 1.2, 1.0} : miss->second;
      int runs = 0, unfinished = 0;
      Figures worst;
      double worst_from = 0;
      unsigned long long worst_seed = 0;
      for (double from : mode.froms) {
        for (int si = 0; si < n_seeds; ++si) {
          const unsigned long long seed = si == 0 ? 12345ULL : static_cast<unsigned long long>(si);
          control::AutotuneResult r{};
          bool sf = false;
          const Figures f = after_u1::after_u1(p, seed, noise, &r, &sf, p.target_c + from, hot_start_mode(mode.name));
          if (r.model.rise_q8 == 0) {  // the tune ended without a result
            ++unfinished;
            continue;
          }
          if (r.unsure) {  // a response that outlasted the history: the relay's figures, as before
            ++unsure;
            std::printf("   unsure %s from %+.0f seed %llu: os %.2f set %.2f p-p %.3f dip %.2f (C %.1f D %.2f)\n",
                        p.name.c_str(), from, seed, f.overshoot_c, f.settling_ratio, f.steady_pp_c, f.dip_c,
                        r.model.time_constant_q8 / 256.0, r.model.dead_time_q8 / 256.0);
            continue;
          }
          ++runs;
          const bool over = !f.ok || f.overshoot_c > 1.0 || f.settling_ratio > 1.2 || f.steady_pp_c > 0.5 || f.dip_c > 1.0;
          const bool met = f.ok && f.overshoot_c <= lim.overshoot_c && f.settling_ratio <= lim.settling_ratio &&
                           f.steady_pp_c <= 0.5 && f.dip_c <= lim.dip_c;
          if (over) {
            ++over_all;
            std::printf("   %s %s from %+.0f seed %llu: os %.2f set %.2f p-p %.3f dip %.2f%s (C %.1f D %.2f F %.1f)\n",
                        met ? "known miss" : "MISS", p.name.c_str(), from, seed, f.overshoot_c, f.settling_ratio,
                        f.steady_pp_c, f.dip_c, f.ok ? "" : " not back in ±1 °C", r.model.time_constant_q8 / 256.0,
                        r.model.dead_time_q8 / 256.0, r.model.fan_loss_pct_q8 / 256.0);
          }
          EXPECT_TRUE(met) << mode.name << " " << p.name << " from " << from << " seed " << seed;
          if (f.overshoot_c > worst.overshoot_c) worst_from = from, worst_seed = seed;
          worst.overshoot_c = std::max(worst.overshoot_c, f.overshoot_c);
          worst.settling_ratio = std::max(worst.settling_ratio, f.settling_ratio);
          worst.steady_pp_c = std::max(worst.steady_pp_c, f.steady_pp_c);
          worst.dip_c = std::max(worst.dip_c, f.dip_c);
        }
      }
      unfinished_all += unfinished;
      runs_all += runs;
      std::printf("%-17s %5d %5d | %8.2f %8.2f %7.3f %6.2f | (%+.0f, %llu)\n", p.name.c_str(), runs, unfinished,
                  worst.overshoot_c, worst.settling_ratio, worst.steady_pp_c, worst.dip_c, worst_from, worst_seed);
    }
  }
  std::printf("%d of %d finished tunes over a target after U1; %d unsure, %d unfinished\n", over_all, runs_all, unsure,
              unfinished_all);
  // The known relay failures and aborts, and unsure tunes, no more.
  if (sweep_env == nullptr && seeds_env == nullptr && noise_env == nullptr && modes_env == nullptr) {
    EXPECT_LE(unfinished_all, kHotUnfinished);
    EXPECT_LE(unsure, kHotUnsure);
  }
}

// The lag a held start reads from the relay's amplitude (Autotune::held_lag_stage, 32-bit
// integers) against the same formula in double precision on the tune's own figures:
// X = (K/T)·Ku·Tu/(2π·255), τ = √(X² − 1)·Tu/(2π). And beside the plant's thermistor lag.
TEST(AutotuneAfterU1, HeldStartLagFromTheRelayAmplitudeMatchesDoublePrecision) {
  const std::vector<after_u1::Plant> ps = after_u1::plants();
  const std::map<std::string, double> true_lag_s = {{"hotend40w", 1 / 0.22}, {"hotend30w", 1 / 0.22},
                                                    {"hotend80w", 1 / 0.22}, {"light-fast", 1.0},
                                                    {"heavy-slow", 25.0}};
  int checked = 0;
  double worst = 0;
  for (const auto& lag : true_lag_s) {
    const after_u1::Plant* p = after_u1::find(ps, lag.first);
    ASSERT_NE(p, nullptr);
    for (double from : {-60.0, -10.0, 20.0}) {
      control::AutotuneResult r{};
      if (!after_u1::tune(*p, 12345, 0.1, &r, p->target_c + from) || r.sensor_lag_q8 == 0) continue;
      ASSERT_TRUE(r.held_gain);
      const double k = r.model.rise_q8 / 256.0, t = r.model.time_constant_q8 / 256.0;
      const double ku = r.ultimate.ku_q8 / 256.0, tu = r.ultimate.tu_q8 / 256.0;
      const double x = (k / t) * ku * tu / (2 * M_PI * 255);
      const double tau = std::sqrt(x * x - 1) * tu / (2 * M_PI);
      const double got = r.sensor_lag_q8 / 256.0;
      std::printf("%-11s from %+3.0f: K %.1f T %.1f Ku %.2f Tu %.2f -> tau %.3f s (double %.3f; plant's lag %.2f s)\n",
                  lag.first.c_str(), from, k, t, ku, tu, got, tau, lag.second);
      worst = std::max(worst, std::fabs(got - tau) / tau);
      EXPECT_NEAR(got, tau, 0.005 * tau + 2.0 / 256) << lag.first << " from " << from;
      EXPECT_EQ(r.model.dead_time_q8, r.sensor_lag_q8) << lag.first;  // τ is M307's D where taken
      ++checked;
    }
  }
  std::printf("worst relative difference %.2e over %d tunes\n", worst, checked);
  EXPECT_GE(checked, 12);  // the lag path ran (14 of these 15 tunes take it; light-fast from S + 20 does not)
}

// hotend40w-delay5 (a 5 s transport delay before a lagging thermistor): the relay's FOPDT reads
// D 6.1–7.8 s, and the one-state design on it settled in 1.43–1.45 × bound (overshoot 0.7–1.5 °C)
// over these seeds. With D ≥ 1.15·Tu/4 where the cut probe peaked late: 1.15–1.19 ×. Since d is
// held over the measured cycles (K within 1 % instead of 3–4 % high), D ≥ Tu/4: 1.07–1.14 ×.
TEST(AutotuneAfterU1, TransportDelayedHotendSettlesWithin1_2BoundOverNoiseSeeds) {
  const std::vector<after_u1::Plant> ps = after_u1::plants();
  const after_u1::Plant* p = after_u1::find(ps, "hotend40w-delay5");
  ASSERT_NE(p, nullptr);
  for (unsigned long long seed : {12345ULL, 1ULL, 2ULL, 3ULL}) {
    control::AutotuneResult r{};
    bool sf = false;
    const Figures f = after_u1::after_u1(*p, seed, 0.1, &r, &sf);
    EXPECT_TRUE(r.late_peak) << "seed " << seed;
    EXPECT_TRUE(sf) << "seed " << seed;
    EXPECT_LE(f.overshoot_c, 1.0) << "seed " << seed;
    EXPECT_LE(f.settling_ratio, 1.2) << "seed " << seed;
    EXPECT_LE(f.steady_pp_c, 0.5) << "seed " << seed;
  }
}

// Hotends whose tune saw a thermistor lag: U1 designs the two-lag state feedback, which settled
// them within the targets over these noise seeds (σ 0.1 °C: seed003 0.86–0.89 ×, heavy-slow
// 0.98–1.01 ×, where the one-state design took 2.06–2.13 × and 1.68–1.70 ×; on the two-node
// hotends, lag ≤ C/20, overshoot ≤ 0.19 °C at 0.95–1.11 ×, where the paced one-state design
// overshot hotend80w by 1.39–1.68 °C at 1.25–1.29 × and hotend40w by 0.44–0.96 °C).
TEST(AutotuneAfterU1, LaggingHotendsGetTheTwoLagDesignAndSettleWithinTheTargets) {
  const std::vector<after_u1::Plant> ps = after_u1::plants();
  for (const char* name : {"seed003", "heavy-slow", "hotend40w", "hotend30w", "hotend80w", "light-fast"}) {
    const after_u1::Plant* p = after_u1::find(ps, name);
    ASSERT_NE(p, nullptr);
    for (unsigned long long seed : {12345ULL, 1ULL, 2ULL, 3ULL}) {
      control::AutotuneResult r{};
      bool sf = false;
      const Figures f = after_u1::after_u1(*p, seed, 0.1, &r, &sf);
      control::TunedDesign d;
      ASSERT_TRUE(control::design_from_tune(r, firmware::kControlPeriodMs, &d)) << name << " seed " << seed;
      control::StateFeedbackConstants k;  // the board designs the two-lag law, not the fallback
      ASSERT_TRUE(control::design_tuned_state_feedback(&d, firmware::kControlPeriodMs, &k)) << name << " seed " << seed;
      EXPECT_TRUE(d.two_lags) << name << " seed " << seed;
      EXPECT_EQ(k.n, 2) << name << " seed " << seed;
      EXPECT_TRUE(sf) << name << " seed " << seed;
      EXPECT_TRUE(f.ok) << name << " seed " << seed;
      EXPECT_LE(f.overshoot_c, 1.0) << name << " seed " << seed;
      EXPECT_LE(f.settling_ratio, 1.2) << name << " seed " << seed;
      EXPECT_LE(f.steady_pp_c, 0.5) << name << " seed " << seed;
      EXPECT_LE(f.dip_c, 1.0) << name << " seed " << seed;
    }
  }
}

// A dead time with a thermistor lag τ2 behind the block (off the bank: two lags and a dead time,
// design::second_order(450, τ1, τ2, D) with the seed fan). The cut probe's peak is flat, and every
// C the tune read took the lag for a longer block (≈ τ1 + 2.4 τ2): 24/2/20 s read C 28.7 and F
// 49.9 %, and after U1 overshot 20.9 °C with a 7.6 °C fan dip; 24/6/16 s C 36.4, 40.3 °C
// (realisation 12345). The heat-up runs open loop within the dead time on that C. The probe now
// reads its tail, where the block's own e^(−t/τ1) is left (Autotune::decay_step), and takes it for
// C and for the fan step's S. Measured (σ 0.1 °C, these realisations): 24/2/20 C 23.9–24.2, F
// 42.4–42.8, overshoot ≤ 0.39 °C, dip ≤ 0.25 °C; 24/6/16 C 25.3–25.5, 3.1–3.6 °C (the lag still
// shows). (24/1/20 reads no tail on some realisations and keeps C 26.2–26.5: not asserted here.)
TEST(AutotuneAfterU1, DeadTimeBehindALagTakesTheBlocksTimeConstantFromTheProbesTail) {
  struct Case {
    double t1, t2, dead;
    double c_tol, overshoot_max_c;
  };
  for (const Case& c : {Case{24, 2, 20, 0.03, 1.0}, Case{24, 6, 16, 0.08, 5.0}}) {
    after_u1::Plant p{"lag+dead", design::with_seed_fan(design::second_order(450, c.t1, c.t2, c.dead)), 210, 400, 700, 1};
    for (unsigned long long seed : {12345ULL, 1ULL, 2ULL}) {
      control::AutotuneResult r{};
      const Figures f = after_u1::after_u1(p, seed, 0.1, &r);
      const double c_s = r.model.time_constant_q8 / 256.0, f_pct = r.model.fan_loss_pct_q8 / 256.0;
      std::printf("%.0f/%.0f/%.0f s seed %llu: C %.2f D %.2f F %.1f | overshoot %.2f °C, settling %.0f s, dip %.2f °C\n", c.t1,
                  c.t2, c.dead, seed, c_s, r.model.dead_time_q8 / 256.0, f_pct, f.overshoot_c, f.settling_s, f.dip_c);
      EXPECT_NEAR(c_s, c.t1, c.c_tol * c.t1) << c.t2 << " seed " << seed;
      EXPECT_NEAR(f_pct, 42.6, 0.05 * 42.6) << c.t2 << " seed " << seed;
      EXPECT_TRUE(f.ok) << c.t2 << " seed " << seed;
      EXPECT_LE(f.overshoot_c, c.overshoot_max_c) << c.t2 << " seed " << seed;
      EXPECT_LE(f.dip_c, 1.5) << c.t2 << " seed " << seed;
    }
  }
}

// A table (as Autotune.Table), whose check is the baseline it sweeps from: the tune finished and
// the board designed from it. Per noise seed the tuned model and the figures of
// the one-state state feedback (paced or not) and of the PID following the model, with the
// design's D replaced by D × factor (AUTOTUNE_SWEEP_TU: Tu/4 × factor). By default
// hotend40w-delay5, one seed; AUTOTUNE_SWEEP="plant,plant", AUTOTUNE_FACTORS="1,1.2",
// AUTOTUNE_SWEEP_SEEDS=n (12345, 1, 2, …), AUTOTUNE_SWEEP_NOISE=σ, AUTOTUNE_SWEEP_TRACE=1 (the
// first seed's heat-ups), AUTOTUNE_SWEEP_LHAT=1 (the probe's cut-to-peak time) for others.
TEST(AutotuneAfterU1, DeadTimeSweepTable) {
  const char* env = std::getenv("AUTOTUNE_SWEEP");
  const int default_seeds = env == nullptr ? 1 : 4;
  if (env == nullptr) env = "hotend40w-delay5";
  const char* fenv = std::getenv("AUTOTUNE_FACTORS");
  std::vector<double> factors;
  {
    std::istringstream fs(fenv ? fenv : "1.0,1.2,1.4,1.6");
    std::string tok;
    while (std::getline(fs, tok, ',')) factors.push_back(std::atof(tok.c_str()));
  }
  const std::vector<after_u1::Plant> ps = after_u1::plants();
  std::istringstream names(env);
  std::string name;
  while (std::getline(names, name, ',')) {
    const after_u1::Plant* p = after_u1::find(ps, name);
    if (p == nullptr) continue;
    const char* senv = std::getenv("AUTOTUNE_SWEEP_SEEDS");
    const int n_seeds = senv ? std::atoi(senv) : default_seeds;
    for (int si = 0; si < n_seeds; ++si) {
      const unsigned long long seed = si == 0 ? 12345ULL : static_cast<unsigned long long>(si);
      control::AutotuneResult r{};
      bool sf = false;
      const char* nenv = std::getenv("AUTOTUNE_SWEEP_NOISE");
      const Figures b = after_u1::after_u1(*p, seed, nenv ? std::atof(nenv) : 0.1, &r, &sf);
      control::TunedDesign d;
      ASSERT_TRUE(control::hotend_model_valid(r.model)) << p->name << " seed " << seed;
      ASSERT_TRUE(control::design_from_tune(r, 128, &d)) << p->name << " seed " << seed;
      std::printf("%s seed %llu: A %.0f C %.1f D %.2f lag %.2f Tu %.2f Ku %.2f unsure %d late %d [rho %.2f Tu/4D %.2f D/C %.3f lag/C %.3f] -> design D %.2f paced %d | U1 %s: os %.2f set %.2fx pp %.3f dip %.2f%s\n",
                  p->name.c_str(), seed, r.model.rise_q8 / 256.0, r.model.time_constant_q8 / 256.0,
                  r.model.dead_time_q8 / 256.0, r.sensor_lag_q8 / 256.0, r.ultimate.tu_q8 / 256.0,
                  r.ultimate.ku_q8 / 256.0, r.unsure, r.late_peak,
                  (r.ultimate.tu_q8 / 4.0) / (1020.0 * r.model.time_constant_q8 / (3.14159 * r.model.rise_q8 * r.ultimate.ku_q8 / 256.0)),
                  r.ultimate.tu_q8 / 4.0 / r.model.dead_time_q8,
                  1.0 * r.model.dead_time_q8 / r.model.time_constant_q8, 1.0 * r.sensor_lag_q8 / r.model.time_constant_q8, d.model.dead_time_q8 / 256.0, d.lag_paced, sf ? "sf" : "pid+ff",
                  b.overshoot_c, b.settling_ratio, b.steady_pp_c, b.dip_c, b.ok ? "" : " FAIL");
      if (std::getenv("AUTOTUNE_SWEEP_TWO_STATE") && (r.sensor_lag_q8 > 0 || std::atoi(std::getenv("AUTOTUNE_SWEEP_TWO_STATE")) >= 2)) {
        // Step-4 estimate: the host's double-precision design (design_constants, as hotend-design)
        // of a two-lag model from the tune: τ1 = C, τ2 = the tune's lag, dead time D − lag.
        // AUTOTUNE_SWEEP_TWO_STATE=2: τ2 = D, no dead time; =3: also τ1 = C − D.
        const int variant = std::atoi(std::getenv("AUTOTUNE_SWEEP_TWO_STATE"));
        const double d_s = r.model.dead_time_q8 / 256.0, c_s = r.model.time_constant_q8 / 256.0;
        const double lag = variant >= 2 ? d_s : r.sensor_lag_q8 / 256.0;
        const double dead = variant >= 2 ? 0.0 : std::max(0.0, d_s - lag);
        const double tau1 = variant == 3 ? c_s - d_s : c_s;
        design::LtiModel m2 = design::second_order(r.model.rise_q8 / 256.0, tau1, lag, dead);
        m2.fan_loss_per_k = r.model.fan_loss_pct_q8 / 25600.0 / (r.model.rise_q8 / 256.0);
        after_u1::Applied a = after_u1::applied(r, d, true);
        const char* err = design::design_constants(m2, &a.sf);
        a.sf_ok = err == nullptr;
        const Figures t = after_u1::run(*p, a);
        std::printf("   two-state (tau1 %.1f tau2 %.2f dead %.2f)%s: os %5.2f set %5.2fx pp %.3f dip %.2f%s\n",
                    tau1, lag, dead, err ? err : "", t.overshoot_c, t.settling_ratio,
                    t.steady_pp_c, t.dip_c, t.ok ? "" : " FAIL");
      }
      for (double m : factors) {
        for (int paced = 0; paced <= 1; ++paced) {
          // The design's rule on a result whose D is the scaled one (no lag margin, no Tu floor).
          control::AutotuneResult rv = r;
          const bool tu_base = std::getenv("AUTOTUNE_SWEEP_TU") != nullptr;  // factors of Tu/4
          rv.model.dead_time_q8 = static_cast<int32_t>(std::lround((tu_base ? r.ultimate.tu_q8 / 4.0 : r.model.dead_time_q8) * m));
          rv.sensor_lag_q8 = 0;
          rv.ultimate.tu_q8 = 0;
          control::TunedDesign v;
          if (!control::design_from_tune(rv, 128, &v)) continue;
          v.lag_paced = paced != 0;
          std::vector<double> tr;
          const Figures s = after_u1::run(*p, after_u1::applied(r, v, true), &tr);
          if (std::getenv("AUTOTUNE_SWEEP_TRACE") && seed == 12345ULL) {
            for (size_t k = 0; k < tr.size() / 2; k += 16)  // every 2.048 s
              std::printf("     t %6.1f e %8.2f duty %.3f\n", (k + 1) * after_u1::kPeriodS, tr[2 * k], tr[2 * k + 1]);
          }
          std::printf("   %s x%.2f = %6.2f paced %d  sf: os %5.2f set %5.2fx pp %.3f dip %.2f%s", tu_base ? "Tu/4" : "D", m,
                      v.model.dead_time_q8 / 256.0, paced, s.overshoot_c, s.settling_ratio, s.steady_pp_c, s.dip_c,
                      s.ok ? "" : " FAIL");
          if (paced == 0) {
            const Figures q = after_u1::run(*p, after_u1::applied(r, v, false));
            std::printf("  | pid+ff: os %5.2f set %5.2fx dip %.2f%s", q.overshoot_c, q.settling_ratio, q.dip_c,
                        q.ok ? "" : " FAIL");
          }
          std::printf("\n");
        }
      }
    }
  }
}

}  // namespace

namespace {

// seed003's tune leaves its model on the loose check (a thermistor lag above C/20). PID and
// fuzzy-PID selected on it with M310 F0 still carry the part fan's share of that model: without
// it the fan step dipped 29 °C and never came back (simavr, RAMPS); with it 5.4–6.1 °C and back
// in ±1 °C within 90–170 s while the tune read F 21 % high. With the heat-up's lag fit (F +7 %)
// this rig measures 1.78 °C / 87 s (PID) and 4.84 °C / 28 s (fuzzy-PID). Fuzzy-PID's heat-up
// follows that loose model too: by feedback alone its rules' cut ki left it −6.9 °C (4.3 °C p-p)
// after 300 s; now it settles in 105 s (PID, by feedback: 211 s) and the fan step costs 1.65 °C.
TEST(AutotuneAfterU1, LooseModelsFanShareReachesThePidFamilyWithF0) {
  const std::vector<after_u1::Plant> ps = after_u1::plants();
  const after_u1::Plant* p = after_u1::find(ps, "seed003");
  ASSERT_NE(p, nullptr);
  control::AutotuneResult r{};
  ASSERT_TRUE(after_u1::tune(*p, 12345, 0.1, &r));
  ASSERT_FALSE(control::tune_bounds_tightly(r));
  control::TunedDesign d;
  ASSERT_TRUE(control::design_from_tune(r, firmware::kControlPeriodMs, &d));
  after_u1::Applied a = after_u1::applied(r, d, false);
  EXPECT_EQ(a.settings.model_tuned, firmware::kModelMeasuredLag);
  a.settings.feedforward = 0;
  for (firmware::ControllerId id : {firmware::ControllerId::kPid, firmware::ControllerId::kFuzzyPid}) {
    a.settings.controller = static_cast<uint8_t>(id);
    static firmware::ControllerBank bank{controller_test::load_cell};
    const firmware::HandOver cold{static_cast<int32_t>(std::lround(p->model.ambient_c * 256)), 0, false};
    bank.init(firmware::default_settings());
    ASSERT_EQ(bank.apply(a.settings, cold), nullptr);
    const heat_fan_step::Result h = heat_fan_step::run(bank, p->model, p->target_c, p->fan_s, p->run_s, 0.05);
    std::printf("seed003 %s F0: overshoot %.2f °C, settled %.1f s, steady mean %.2f p-p %.2f °C; fan step |error| %.2f °C, back in ±1 °C after %.1f s\n",
                id == firmware::ControllerId::kPid ? "pid" : "fuzzy", h.overshoot_c, h.settling_s, h.steady_mean_c,
                h.steady_pp_c, h.dip_c, h.recovery_s);
    // The heat-up by HIL3's limits (sim/CMakeLists.txt): within ±1 °C before the steady window,
    // no offset, no oscillation, overshoot ≤ 3 °C.
    EXPECT_LE(h.overshoot_c, 3.0) << static_cast<int>(id);
    EXPECT_LT(h.settling_s, 0.75 * p->fan_s) << static_cast<int>(id);
    EXPECT_LE(std::fabs(h.steady_mean_c), 0.5) << static_cast<int>(id);
    EXPECT_LE(h.steady_pp_c, 1.0) << static_cast<int>(id);
    EXPECT_LE(h.dip_c, 8.0) << static_cast<int>(id);
    EXPECT_GE(h.recovery_s, 0.0) << static_cast<int>(id);
    EXPECT_LE(h.recovery_s, 200.0) << static_cast<int>(id);
  }
}

}  // namespace
