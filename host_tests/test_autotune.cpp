// The M303 identification engine (control/autotune.h) on simulated hotends (design/plant_sim.h):
// finishes, never above target + 5 °C, within the duration targets, and identifies K, T, L, F.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "control/autotune.h"
#include "control/autotune_design.h"
#include "control/feedforward.h"
#include "control/pid.h"
#include "design/lti_model.h"
#include "design/seed_models.h"
#include "design/plant_sim.h"
#include "host_tests/lag_delay_hotend.h"
#include "host_tests/hot_start_rig.h"

namespace {

using control::Autotune;
using control::AutotuneFailure;
using control::AutotuneState;

constexpr double kPeriodS = 0.128;

struct Plant {
  std::string name;
  design::LtiModel model;
  double target_c;
  double start_c;       // 25 = cold; else held there by a steady duty before the tune
  bool fopdt;           // K, T, L, F accuracy asserted
  double k, t, l, lag;  // true values (lag: the second lag, 0 if none)
  double budget_s;      // duration target (0: full-power heat-up + 180 s)
};

double fan_pct(const design::LtiModel& m, double k) { return m.fan_loss_per_k * k * 100.0; }

Plant fopdt_plant(const std::string& name, double k, double t, double l, double target = 210) {
  design::LtiModel m = design::with_seed_fan(design::fopdt(k, t, l));
  return Plant{name, m, target, 25, true, k, t, l, 0, 0};
}

Plant two_node_plant(const std::string& name, design::TwoNodeParams p, double target = 210, double delay = 0) {
  design::LtiModel m = design::two_node(p);
  m.delay_s = delay;
  const double k = p.heater_w / p.loss_w_per_k;
  return Plant{name, m, target, 25, false, k, p.block_j_per_k / p.loss_w_per_k, delay, 1.0 / p.sensor_rate_per_s, 0};
}

std::vector<Plant> plants() {
  std::vector<Plant> v;
  Plant h = two_node_plant("hotend40w", design::TwoNodeParams());
  h.budget_s = 240;
  v.push_back(h);
  v.push_back(fopdt_plant("seed002", 450, 24, 20.7));
  v.push_back(fopdt_plant("seed004", 450, 25.5, 19.5));
  Plant s3{"seed003", design::seed003(), 210, 25, false, 450, 0.64 * 44.2696, 0, 0.32 * 44.2696, 0};
  v.push_back(s3);
  v.push_back(fopdt_plant("fopdt-60-3", 450, 60, 3));
  v.push_back(fopdt_plant("fopdt-300-10", 450, 300, 10));
  v.push_back(fopdt_plant("fopdt-120-25", 450, 120, 25));
  v.push_back(fopdt_plant("fopdt-30-1", 450, 30, 1));
  design::TwoNodeParams p30;
  p30.heater_w = 30;
  v.push_back(two_node_plant("two-node-30W", p30));
  design::TwoNodeParams p80;
  p80.heater_w = 80;
  v.push_back(two_node_plant("two-node-80W", p80));
  design::TwoNodeParams light;
  light.block_j_per_k = 6;
  light.sensor_rate_per_s = 1.0;
  v.push_back(two_node_plant("light-fast", light));
  design::TwoNodeParams heavy;
  heavy.block_j_per_k = 40;
  heavy.heater_w = 60;
  heavy.loss_w_per_k = 0.14;
  heavy.loss_fan_w_per_k = 0.2;
  heavy.sensor_rate_per_s = 1.0 / 25;
  v.push_back(two_node_plant("heavy-slow", heavy));
  v.push_back(two_node_plant("two-node-delay5", design::TwoNodeParams(), 210, 5.0));
  Plant s4{"seed000-4", design::seed000_4(), 150, 25, false, 450, 0, 0, 0, 2 * 730.7};
  Plant s5{"seed000-5", design::seed000_5(), 150, 25, false, 450, 0, 0, 0, 2 * 664.0};
  v.push_back(s4);
  v.push_back(s5);
  return v;
}

struct TuneRun {
  AutotuneState state = AutotuneState::kIdle;
  AutotuneFailure failure = AutotuneFailure::kNone;
  double duration_s = 0;
  double max_c = -1e9;
  double heatup_s = 0;  // full-power heat-up to the target from the same start
  control::AutotuneResult result{};
  int cycles = 0;
  double approach_s = 0, relay_s = 0, fan_s = 0;  // when each began
  bool lag_probe = false;  // the approach took the probe for a sensor lag (D + (L̂ − D)/2.5)
  double max_at_s = 0;
  int overruns = 0;  // bins whose staged logic did not finish before the next bin
};

// Time for 100 % duty to bring the plant from its start to the target.
double full_power_heatup_s(const Plant& p, double start_duty) {
  design::PlantSim sim(p.model);
  for (int i = 0; i < 40000 && start_duty > 0; ++i) sim.run(start_duty, kPeriodS);
  const double t0 = sim.time_s();
  while (sim.true_c() < p.target_c && sim.time_s() - t0 < 5000) sim.run(1.0, kPeriodS);
  return sim.time_s() - t0;
}

TuneRun run(const Plant& p, uint8_t cycles = 3, bool fan = true, double noise = 0.1, bool trace = false,
        double heater_scale = 1.0, double start_c = -1, bool heater_stuck_on = false, uint16_t timeout_s = 3600,
        unsigned long long noise_seed = 12345, bool after_m109 = false, bool hold_gain = true) {
  TuneRun r;
  if (start_c < 0) start_c = p.start_c;
  design::PlantSim sim(p.model);
  sim.set_noise(noise);
  sim.set_noise_seed(noise_seed);
  sim.set_gain_error(heater_scale);
  double start_duty = 0;
  if (after_m109) {
    host_rig::heat_as_m109(sim, start_c);  // as `M109 S<start>` then M303
  } else if (start_c > 25.5) {
    start_duty = host_rig::hold_at(sim, p.model, start_c);  // as a printer idling there
  }
  r.heatup_s = full_power_heatup_s(p, start_duty);
  Autotune at;
  at.configure(128, timeout_s);
  // A held start gives the tune the hold's static gain, as the firmware's SteadyHold measures it
  // (mean reading − 25 °C over mean duty; the rig holds it exactly): hold_gain false, none.
  const int32_t hold_gain_q8 = hold_gain && start_duty > 0 ? host_rig::held_gain_q8(start_c, start_duty) : 0;
  at.start(static_cast<int32_t>(std::lround(p.target_c * 256)), cycles, fan, Autotune::kMeasureAmbient, hold_gain_q8);
  const double t0 = sim.time_s();
  bool below = false;
  for (int i = 0; i < 160000; ++i) {
    const double m = sim.measured_c();
    const control::AutotuneOutput out = at.step(static_cast<int32_t>(std::lround(m * 256)));
    if (at.phase() == Autotune::Phase::kApproach && r.approach_s == 0) {
      r.approach_s = sim.time_s() - t0;
      r.lag_probe = at.lag_probe();
    }
    if (at.phase() == Autotune::Phase::kRelay && r.relay_s == 0) r.relay_s = sim.time_s() - t0;
    if (out.fan_duty > 0 && r.fan_s == 0) r.fan_s = sim.time_s() - t0;
    if (out.event == control::AutotuneEvent::kCycle || out.event == control::AutotuneEvent::kUltimate) ++r.cycles;
    if (trace && (i % 8 == 0 || out.event != control::AutotuneEvent::kNone)) {
      std::printf("%7.1f ph%d y %7.2f duty %5.3f fan %3d S %d L %d invT %d ev %d untrusted %d law %d lag %d\n", sim.time_s() - t0,
                  static_cast<int>(at.phase()), sim.true_c(), out.duty_q16 / 65535.0, out.fan_duty, at.slope_q8(),
                  at.horizon_ticks(), at.inv_t_q16(), static_cast<int>(out.event), at.untrusted(), at.approach_law(), at.lag_probe());
    }
    if (out.state != AutotuneState::kRunning) {
      r.state = out.state;
      r.failure = out.failure;
      break;
    }
    sim.set_fan(out.fan_duty / 255.0);
    sim.run(heater_stuck_on ? 1.0 : out.duty_q16 / 65535.0, kPeriodS);
    // Max from the first moment at or below the target (a start above it cools first).
    if (sim.true_c() <= p.target_c) below = true;
    if (below && sim.true_c() > r.max_c) {
      r.max_c = sim.true_c();
      r.max_at_s = sim.time_s() - t0;
    }
  }
  r.duration_s = sim.time_s() - t0;
  r.result = at.result();
  r.overruns = at.overruns();
  return r;
}

double q8(int32_t v) { return v / 256.0; }

TEST(Autotune, Table) {
  std::printf("%-16s %6s %6s %6s %6s | %7s %7s | %6s %6s | %6s %6s | %5s %5s | %5s\n", "plant", "dur s", "budget", "maxS", "cyc",
              "K id", "K true", "T id", "T true", "L id", "L true", "F id", "F tru", "lag");
  // AUTOTUNE_TRACE=<plant> prints that plant's run bin by bin first (a diagnostic, not a test).
  // AUTOTUNE_CYCLES=<C> runs that many relay cycles (default 3; M303's default is 5).
  const char* trace = std::getenv("AUTOTUNE_TRACE");
  const char* cycles_env = std::getenv("AUTOTUNE_CYCLES");
  const uint8_t cycles = static_cast<uint8_t>(cycles_env != nullptr ? std::atoi(cycles_env) : 3);
  const char* noise_env = std::getenv("AUTOTUNE_NOISE");  // reading noise σ °C (0.1)
  const double noise = noise_env != nullptr ? std::atof(noise_env) : 0.1;
  const char* seed_env = std::getenv("AUTOTUNE_SEED");  // another noise realisation (12345)
  const unsigned long long seed = seed_env != nullptr ? std::strtoull(seed_env, nullptr, 10) : 12345;
  // AUTOTUNE_FROM=<°C from the target> starts each plant held there (a hot start; −60: a standby
  // temperature, +20: above the target), AUTOTUNE_TARGET_SHIFT=<°C> moves each plant's target.
  const char* from_env = std::getenv("AUTOTUNE_FROM");
  const char* shift_env = std::getenv("AUTOTUNE_TARGET_SHIFT");
  // AUTOTUNE_M109=1: the start reached as M109 reaches it (the default PID from cold; see run()).
  const bool after_m109 = std::getenv("AUTOTUNE_M109") != nullptr;
  // AUTOTUNE_NOHOLD=1: a held start without the hold's static gain (as M303 sent within 65 s).
  const bool hold_gain = std::getenv("AUTOTUNE_NOHOLD") == nullptr;
  for (Plant p : plants()) {
    if (shift_env != nullptr) p.target_c += std::atof(shift_env);
    const double start_c = from_env != nullptr ? p.target_c + std::atof(from_env) : -1;
    TuneRun r = run(p, cycles, true, noise, trace != nullptr && p.name == trace, 1.0, start_c, false, 1800, seed,
                    after_m109 && start_c > 0, hold_gain);  // the firmware's limit
    const double budget = p.budget_s > 0 ? p.budget_s : r.heatup_s + 180;
    std::printf("%-16s %6.1f %6.1f %6.2f %6d | %7.1f %7.1f | %6.2f %6.1f | %6.2f %6.2f | %5.1f %5.1f | %5.2f | %5.0f %5.0f %5.0f max@%4.0f %s%s\n", p.name.c_str(),
                r.duration_s, budget, r.max_c - p.target_c, r.cycles, q8(r.result.model.rise_q8), p.k,
                q8(r.result.model.time_constant_q8), p.t, q8(r.result.model.dead_time_q8), p.l,
                q8(r.result.model.fan_loss_pct_q8), fan_pct(p.model, p.k), p.lag, r.approach_s, r.relay_s, r.fan_s, r.max_at_s,
                r.state == AutotuneState::kFinished ? "" : " FAILED ", r.state == AutotuneState::kFinished ? "" : std::to_string(static_cast<int>(r.failure)).c_str());
  }
}


// What the issue asks, per plant. Misses measured at this commit are listed by name with the
// measured figure so that the table in the report and these tests agree; anything else failing is
// a regression.
// Slow plants whose probe model is untrusted (response beyond the model history, or no clean
// peak) or lag-type with a long lag: the tune goes slowly and safely; it finishes within the
// firmware's limit (1800 s grown by the measured response time), not within the duration target.
const std::set<std::string> kSeed000 = {"seed000-4", "seed000-5", "heavy-slow"};

bool in(const std::set<std::string>& s, const std::string& n) { return s.count(n) > 0; }

class AutotunePlants : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    runs_ = new std::vector<TuneRun>();
    for (const Plant& p : plants()) runs_->push_back(run(p, 3, true, 0.1, false, 1.0, -1, false, 1800));
  }
  static void TearDownTestSuite() { delete runs_; }
  static std::vector<TuneRun>* runs_;
};
std::vector<TuneRun>* AutotunePlants::runs_ = nullptr;

TEST_F(AutotunePlants, FinishAndStayWithinTargetPlus5) {
  const std::vector<Plant> ps = plants();
  for (size_t i = 0; i < ps.size(); ++i) {
    const Plant& p = ps[i];
    const TuneRun& r = (*runs_)[i];
    EXPECT_EQ(r.state, AutotuneState::kFinished) << p.name << " failure " << static_cast<int>(r.failure);
    EXPECT_EQ(r.overruns, 0) << p.name;
    EXPECT_LE(r.max_c, p.target_c + 5.0) << p.name;
  }
}

// A cold cut probe that peaks 2.5–4 × the relay's D after the cut marks a lag the relay's FOPDT
// folded into D (control/autotune_design.cpp then takes D from Tu): two-node-delay5 only.
TEST_F(AutotunePlants, OnlyTheTransportDelayedLagPeaksLate) {
  const std::vector<Plant> ps = plants();
  for (size_t i = 0; i < ps.size(); ++i) {
    const control::AutotuneResult& r = (*runs_)[i].result;
    std::printf("%-16s late_peak %d unsure %d lag %.2f\n", ps[i].name.c_str(), r.late_peak, r.unsure, q8(r.sensor_lag_q8));
    if (in(kSeed000, ps[i].name) && r.unsure) continue;  // the design leaves an unsure model's D alone
    EXPECT_EQ(r.late_peak, ps[i].name == "two-node-delay5") << ps[i].name;
  }
}

TEST_F(AutotunePlants, IdentifyFopdtPlantsWithin10PercentAndFanWithin20) {
  const std::vector<Plant> ps = plants();
  // Known miss: fopdt-30-1's dead time 1 s comes out 0.85–0.90 s (−10..−15 %: 0.1 s is under
  // one control period). fopdt-60-3's relay T reads +8..+16 % (at L/T = 0.05 its 1 − θ is a 5 %
  // ratio of two amplitudes); the cut probe's C, taken within 20 % of it, reads −0.1..+1.3 %
  // (σ 0.1, 20 noise seeds).
  for (size_t i = 0; i < ps.size(); ++i) {
    const Plant& p = ps[i];
    const TuneRun& r = (*runs_)[i];
    if (!p.fopdt) continue;
    const control::HotendModel& m = r.result.model;
    EXPECT_NEAR(q8(m.rise_q8), p.k, 0.10 * p.k) << p.name;
    EXPECT_NEAR(q8(m.time_constant_q8), p.t, 0.10 * p.t) << p.name;
    if (p.name != "fopdt-30-1") {
      EXPECT_NEAR(q8(m.dead_time_q8), p.l, 0.10 * p.l) << p.name;
    }
    EXPECT_NEAR(q8(m.fan_loss_pct_q8), fan_pct(p.model, p.k), 0.20 * fan_pct(p.model, p.k)) << p.name;
  }
}

// The blind heat-up after U1 on a dead-time hotend (full power ends before the dead time shows
// anything) lands where A·(1 − e^(−t/C)) says: 1 % of C is ~2 °C there. The cut probe's peak
// gives C within 1 % at σ 0.1 °C (the relay's formulas alone: −5.6..+4.7 % over these runs).
TEST(Autotune, CutProbeTimeConstantWithin1PercentOnDeadTimePlants) {
  for (const Plant& p : plants()) {
    if (p.name != "seed002" && p.name != "seed004") continue;
    for (unsigned long long seed : {12345ULL, 1ULL, 2ULL, 3ULL}) {
      const TuneRun r = run(p, 3, true, 0.1, false, 1.0, -1, false, 1800, seed);
      ASSERT_EQ(r.state, AutotuneState::kFinished) << p.name << " seed " << seed;
      EXPECT_NEAR(q8(r.result.model.time_constant_q8), p.t, 0.01 * p.t) << p.name << " seed " << seed;
    }
  }
}

TEST_F(AutotunePlants, IdentifyTwoNodeGainAndFanLoss) {
  const std::vector<Plant> ps = plants();
  for (size_t i = 0; i < ps.size(); ++i) {
    const Plant& p = ps[i];
    const TuneRun& r = (*runs_)[i];
    if (p.fopdt || p.name.compare(0, 4, "seed") == 0 || in(kSeed000, p.name)) continue;
    EXPECT_NEAR(q8(r.result.model.rise_q8), p.k, 0.10 * p.k) << p.name;
    EXPECT_NEAR(q8(r.result.model.fan_loss_pct_q8), fan_pct(p.model, p.k), 0.20 * fan_pct(p.model, p.k)) << p.name;
  }
}

TEST_F(AutotunePlants, DurationTargets) {
  const std::vector<Plant> ps = plants();
  // Met since the fan part is an open-loop step and C3–5 measure 2 relay cycles (C3, σ 0.1 °C):
  // hotend40w 201 s (≤ 240), two-node-30W 235 s, two-node-80W 190 s, light-fast 87 s, fopdt-30-1
  // 135 s, fopdt-60-3 157 s. The rest are in docs/autotune.md with their figures (dead-time-dominated
  // ones: the approach alone takes ~6 × its τ ≈ L̂, a relay period is ≥ 4 L̂).
  const std::set<std::string> met = {"hotend40w", "two-node-30W", "two-node-80W", "light-fast", "fopdt-30-1", "fopdt-60-3"};
  for (size_t i = 0; i < ps.size(); ++i) {
    const Plant& p = ps[i];
    const TuneRun& r = (*runs_)[i];
    const double budget = p.budget_s > 0 ? p.budget_s : r.heatup_s + 180;
    if (in(met, p.name)) {
      EXPECT_LE(r.duration_s, budget) << p.name;
    }
  }
}

// M303 (C5 F1) on p from cold, until the probe hands over to the approach (its model is then set):
// false if the tune did not start or stopped first.
bool probe_until_approach(const Plant& p, design::PlantSim& sim, Autotune& at) {
  at.configure(128);
  if (!at.start(static_cast<int32_t>(p.target_c * 256), 5, true)) return false;
  while (at.phase() != Autotune::Phase::kApproach && at.state() == AutotuneState::kRunning) {
    const control::AutotuneOutput out = at.step(static_cast<int32_t>(std::lround(sim.measured_c() * 256)));
    sim.run(out.duty_q16 / 65535.0, kPeriodS);
  }
  return at.phase() == Autotune::Phase::kApproach;
}

// The probe → approach → relay part on the FOPDT dead-time plants: on those whose cut probe
// peaks sharply (seed002, seed004) the loss rate from the decay after the peak's bin within 3 %
// (from the peak's own bin, which rounds a sharp peak off, seed004 read 1/T 22 % low and its
// approach stalled 25 °C short), and the deadbeat approach on the aligned predictor settled for
// the relay within the full-power heat-up + 4.5 L after the probe (the slow law took 151 and 158
// s: 7–8 L). (fopdt-120-25's flat peak keeps the slow law: FlatPeakBehindATransportDelay...)
TEST(AutotuneApproach, FopdtDeadTimePlantsLandWithinHeatupPlusFourAndAHalfL) {
  for (const Plant& p : plants()) {
    if (p.name != "seed002" && p.name != "seed004") continue;
    design::PlantSim sim(p.model);
    sim.set_noise(0.1);
    Autotune at;
    ASSERT_TRUE(probe_until_approach(p, sim, at)) << p.name;
    const double inv_t = at.inv_t_q16() / 65536.0, inv_t_true = Autotune::kTicksPerBin * kPeriodS / p.t;
    std::printf("%-8s 1/T per bin %.5f (true %.5f)\n", p.name.c_str(), inv_t, inv_t_true);
    EXPECT_NEAR(inv_t, inv_t_true, 0.03 * inv_t_true) << p.name;
    const TuneRun r = run(p, 5, true, 0.1, false, 1.0, -1, false, 1800);
    std::printf("%-8s approach %.1f s, relay %.1f s: %.1f s (heat-up %.1f + 4.5 L %.1f)\n", p.name.c_str(), r.approach_s,
                r.relay_s, r.relay_s - r.approach_s, r.heatup_s, 4.5 * p.l);
    EXPECT_LE(r.relay_s - r.approach_s, r.heatup_s + 4.5 * p.l) << p.name;
    EXPECT_LE(r.max_c, p.target_c + 2.0) << p.name;
  }
}

// A slow FOPDT's cut probe peaks flat, and its highest bin, which the noise picks anywhere on the
// plateau, read L̂ 12.3 s for fopdt-300-10's 10, 4.1 s for fopdt-60-3's 3 and 25.6 s for
// fopdt-120-25's 25. Where the rise is the pulse's own ramp, L̂ is the tangent's (probe stage 5):
// within 5 % or two ticks here (measured 9.86–10.24, 2.94–3.20 and 24.96 s at σ 0.02–0.3 °C).
// A lag-type hotend's probe is no ramp (two-node-delay5: peak ≈ 1.9 × the steepest slope × the
// pulse) and keeps its cut-to-peak time (17–25 s; its tangent is ~6 s).
TEST(AutotuneProbe, AFlatFopdtProbeTakesItsDeadTimeFromTheRampsTangent) {
  int matched = 0;
  for (const Plant& p : plants()) {
    if (!in({"fopdt-300-10", "fopdt-60-3", "fopdt-120-25", "two-node-delay5"}, p.name)) continue;
    ++matched;
    for (const double noise : {0.02, 0.1, 0.3}) {
      for (const unsigned long long seed : {1ULL, 2ULL, 3ULL}) {
        design::PlantSim sim(p.model);
        sim.set_noise(noise);
        sim.set_noise_seed(seed);
        Autotune at;
        ASSERT_TRUE(probe_until_approach(p, sim, at)) << p.name << " σ " << noise << " seed " << seed;
        const double l_s = at.horizon_ticks() * kPeriodS;
        std::printf("%-16s σ %.2f seed %llu: L̂ %.2f s\n", p.name.c_str(), noise, seed, l_s);
        if (p.name == "two-node-delay5") {
          EXPECT_GT(l_s, 15.0) << "σ " << noise << " seed " << seed;
        } else {
          EXPECT_NEAR(l_s, p.l, std::max(0.05 * p.l, 2 * kPeriodS)) << p.name << " σ " << noise << " seed " << seed;
        }
      }
    }
  }
  EXPECT_EQ(matched, 4);
}

// Cut probes that peak late against their response (a sensor lag, not a dead time): heavy-slow
// (a 25 s lag on a 286 s block: response 5 s after the pulse began, peak 66 s after the cut) and
// two-node-delay5 (5 s transport delay, then a 4.6 s lag: 7 s and 22 s). With L̂ as the
// predictor's dead time the approach over-predicted the heat in flight: heavy-slow cut full power
// 80 °C short and crawled, two-node-delay5 crawled its last 10 °C; from the probe to the relay
// (σ 0.1 °C, these realisations) 650–1,040 and 250–300 s. On D + (L̂ − D)/2.5 (docs/autotune.md)
// 417–444 and 164–186 s.
TEST(AutotuneApproach, ALagTypeProbeApproachesOnTheLagNotOnTheCutToPeakTime) {
  // Which probes count as a lag on the bank (σ 0.1 °C): only these two. A dead time delays the
  // response as much as the peak (the FOPDT plants, seed002/004); the two-node plants' and
  // seed003's probes take the tangent (continuous) path; seed000's are retried (nothing within a
  // minute of the first pulse).
  const std::vector<Plant> ps = plants();
  for (const Plant& p : ps) {
    const TuneRun r = run(p, 5, true, 0.1, false, 1.0, -1, false, 1800);
    EXPECT_EQ(r.lag_probe, p.name == "heavy-slow" || p.name == "two-node-delay5") << p.name;
  }
  struct Case { const char* plant; double approach_s; };
  for (const Case c : {Case{"heavy-slow", 500}, Case{"two-node-delay5", 220}}) {
    const auto p = std::find_if(ps.begin(), ps.end(), [&](const Plant& q) { return q.name == c.plant; });
    ASSERT_NE(p, ps.end());
    for (const unsigned long long seed : {12345ULL, 1ULL, 2ULL, 3ULL, 4ULL, 5ULL, 6ULL, 7ULL}) {
      const TuneRun r = run(*p, 5, true, 0.1, false, 1.0, -1, false, 1800, seed);
      std::printf("%-16s seed %5llu: approach %.1f s, tune %.1f s, max S + %.2f\n", c.plant, seed, r.relay_s - r.approach_s,
                  r.duration_s, r.max_c - p->target_c);
      EXPECT_EQ(r.state, AutotuneState::kFinished) << c.plant << " seed " << seed;
      EXPECT_LE(r.relay_s - r.approach_s, c.approach_s) << c.plant << " seed " << seed;
      EXPECT_LE(r.max_c, p->target_c + 2.0) << c.plant << " seed " << seed;
    }
  }
}

// A cold cut probe too flat to show the loss (fopdt-120-25, fopdt-300-10) heats at full power on
// a model without loss until the loss is learnt at full power, over 40 °C. The history built
// without it over-predicted the heat in flight: fopdt-120-25 cut at 137 °C, landed 20 °C short
// and crept for 110 s, then ran a settling relay cycle. Now the history restarts with the loss
// learnt, and an approach that settled needs no settling cycle, as after a sharp peak. Before,
// over these realisations: fopdt-120-25 614–688 s with 3 relay cycles, fopdt-300-10 464 s at
// σ 0 (465–507 at σ 0.1); then 452–524 s with 2, and 392 s (417–493, 3 cycles on 4 of 6).
// With L̂ from the ramp's tangent, S with the pulse's loss and the landing read at L̂ (probe stage
// 5, approach stage 9, landed 4): fopdt-120-25 455 s at σ 0 (438–488 at σ 0.1), fopdt-300-10 362 s
// (361–373), each with 2; with the fan window ended at 16 σ of fall after such a probe 445 s
// (428–478) and 343 s (342–354). fopdt-120-25's landing now takes the settled hold (no relay
// cycle: AutotuneSettledHold): 196 s at σ 0 (191–241 at σ 0.1).
TEST(AutotuneApproach, AFlatPeakFopdtLandsOnTheLossLearntAtFullPower) {
  const std::vector<Plant> ps = plants();
  struct Case { const char* plant; double tune_s[2]; };  // at σ 0 and 0.1
  for (const Case c : {Case{"fopdt-120-25", {200, 250}}, Case{"fopdt-300-10", {360, 370}}}) {
    const auto p = std::find_if(ps.begin(), ps.end(), [&](const Plant& q) { return q.name == c.plant; });
    ASSERT_NE(p, ps.end());
    for (const int n : {0, 1}) {
      const double noise = 0.1 * n;
      for (const unsigned long long seed : {12345ULL, 1ULL, 2ULL, 3ULL, 4ULL, 5ULL}) {
        const TuneRun r = run(*p, 5, true, noise, false, 1.0, -1, false, 1800, seed);
        std::printf("%-14s σ %.1f seed %5llu: approach %.1f s, relay %.1f s, tune %.1f s, cycles %d, max S + %.2f, D %.2f\n", c.plant,
                    noise, seed, r.relay_s - r.approach_s, r.fan_s - r.relay_s, r.duration_s, r.cycles, r.max_c - p->target_c,
                    r.result.model.dead_time_q8 / 256.0);
        EXPECT_EQ(r.state, AutotuneState::kFinished) << c.plant << " seed " << seed;
        EXPECT_LE(r.max_c, p->target_c + 2.0) << c.plant << " seed " << seed;
        EXPECT_LE(r.duration_s, c.tune_s[n]) << c.plant << " σ " << noise << " seed " << seed;
        EXPECT_NEAR(r.result.model.dead_time_q8 / 256.0, p->l, 0.1 * p->l) << c.plant << " seed " << seed;
        // fopdt-120-25: the settled hold, no relay; fopdt-300-10 (L̂ + 2 bins < C/5): the relay's
        // two measured cycles, no settling one.
        EXPECT_EQ(r.cycles, p->name == "fopdt-120-25" ? 0 : 2) << c.plant << " seed " << seed;
      }
    }
  }
}

// FOPDT hotends beyond the bank: K 250–900 °C, C 60–400 s, D 3–35 s, σ 0 and 0.1 °C (cut
// probes, sharp and flat, with and without a loss shown). Every tune finishes within S + 5 °C
// with K and C within 5 % and D within 12 %. The first form of the flat probe's relay without a
// settling cycle started it on an approach still drifting down from S + 2.4 °C, and read
// K 450 C 300 D 35 as D 51. The summed tune time guards the flat probes' gain: 99,846 s before,
// 89,621 s since (89,060 by 2026-12-07), 82,427 s with the flat probe timed by its ramp's
// tangent (80,400 with its fan window ended at 16 σ of fall, 77,653 with the settled hold after
// its landing); a fast landing's swing counted as settled in a ±1 °C window read K 900 C 200 D 3
// as D 3.5 (the window now waits L̂ + 2 bins within 2 °C first).
TEST(AutotuneApproach, FopdtGridFinishesAccurateWithinTargetPlus5) {
  double total_s = 0;
  for (const double k : {250.0, 450.0, 900.0}) {
    for (const double t : {60.0, 120.0, 200.0, 300.0, 400.0}) {
      for (const double l : {3.0, 6.0, 10.0, 15.0, 25.0, 35.0}) {
        for (const double noise : {0.0, 0.1}) {
          const Plant p = fopdt_plant("grid", k, t, l);
          const TuneRun r = run(p, 5, true, noise, false, 1.0, -1, false, 3600, 7);
          const control::HotendModel& m = r.result.model;
          std::ostringstream where;
          where << "K " << k << " C " << t << " D " << l << " σ " << noise;
          ASSERT_EQ(r.state, AutotuneState::kFinished) << where.str();
          EXPECT_LE(r.max_c, p.target_c + 5.0) << where.str();
          EXPECT_NEAR(m.rise_q8 / 256.0, k, 0.05 * k) << where.str();
          EXPECT_NEAR(m.time_constant_q8 / 256.0, t, 0.05 * t) << where.str();
          EXPECT_NEAR(m.dead_time_q8 / 256.0, l, 0.12 * l) << where.str();
          total_s += r.duration_s;
        }
      }
    }
  }
  std::printf("180 FOPDT tunes: %.0f s in all\n", total_s);
  EXPECT_LE(total_s, 82000.0);
}

// M303's default effort (C5, F1): the tune's duration per plant against issue 7's target (≤ 4 min
// on hotend40w-class plants, ≤ the full-power heat-up + 3 min elsewhere, 2 × that on seed000).
// Where it is met, the target is asserted; elsewhere a ceiling ~10 % above the figure measured
// when the fan part became an open-loop step (relay-only tune before, s: seed002 918, seed004
// 904, seed003 379, fopdt-300-10 746, fopdt-120-25 1378, heavy-slow 2281, two-node-delay5 975,
// seed000-4 5196, seed000-5 4407; with the closed-loop fan hold: 634, 616, 324, 565, 986, 1896,
// 781, 2446, 2803; with the fan step: 453, 446, 266, 516, 766, 1589, 681, 2344, 2540; with the
// deadbeat approach (sharp probe peaks) and no settling cycle after it too: seed002 335, seed004
// 336, the rest unchanged; with the full-power approach after a probe that showed no loss:
// fopdt-120-25 657, two-node-delay5 547; with the untrusted approach's heater off above the
// target: seed000-4 2344 → 2917 on this noise realisation, −1.4..+0.1 % mean over 20 others at
// σ 0.1–0.3; with a lag-type probe's approach on the lag: heavy-slow 1586 → 981, two-node-delay5
// 547 → 444; with the loss learnt at full power rebuilding a flat probe's history and no settling
// cycle after it: fopdt-120-25 657 → 462, fopdt-300-10 507 → 445; with the loss learnt near the
// target unblocked by its own ū steps: seed003 274 → 238; with a flat FOPDT probe timed by its
// ramp's tangent: fopdt-300-10 445 → 362, fopdt-120-25 462 → 472; and its fan window ended at
// 16 σ of fall: fopdt-300-10 362 → 343, its target met, fopdt-120-25 472 → 461; and the settled
// hold after its tangent-timed landing: fopdt-120-25 461 → 221, its target met), so a slower tune
// fails here.
TEST(AutotuneDuration, DefaultEffortC5PerPlant) {
  const std::map<std::string, double> ceiling = {
      {"seed003", 262},
      {"heavy-slow", 1050},  {"two-node-delay5", 490}, {"seed000-4", 3000},
      {"seed000-5", 2795}};
  std::printf("%-16s %7s %7s %6s %8s %7s %7s %7s\n", "plant", "tune s", "target", "max-S", "approach", "relay", "fan", "heatup");
  for (const Plant& p : plants()) {
    const TuneRun r = run(p, 5, true, 0.1, false, 1.0, -1, false, 1800);
    const double target = p.budget_s > 0 ? p.budget_s : r.heatup_s + 180;
    // (seed000: budget_s is already 2 × hotend-sim's physical bound, 730.7 / 664.0 s)
    std::printf("%-16s %7.1f %7.1f %6.2f %8.1f %7.1f %7.1f %7.1f\n", p.name.c_str(), r.duration_s, target,
                r.max_c - p.target_c, r.approach_s, r.relay_s, r.fan_s, r.heatup_s);
    EXPECT_EQ(r.state, AutotuneState::kFinished) << p.name;
    EXPECT_LE(r.max_c, p.target_c + 5.0) << p.name;
    const auto c = ceiling.find(p.name);
    EXPECT_LE(r.duration_s, c == ceiling.end() ? target : c->second) << p.name;
  }
}

// A dead-time-dominated FOPDT hotend (L̂ + 2 bins ≥ C/5) whose sharp cut probe's deadbeat approach landed
// and settled needs no relay (control/autotune.cpp, settled_hold): the settled window gives A, the
// probe C and D, and the fan step follows (no relay cycle: Ku/Tu 0). seed002 / seed004 at σ 0.1:
// 335 / 336 → 169 / 175 s, within issue 7's bound + 3 min (213 s). Over σ 0.02–0.5 and 8 noise
// realisations 48 of 64 such tunes took the hold (the others' approaches left the band and kept
// the relay, as before): A within 0.6 %, C 1.9 %, D 1.8 %, F 41.2–44.4 % (42.6). Likewise after a
// flat probe timed by its ramp's tangent (landed 4) where L̂ + 2 bins ≥ C/5: fopdt-120-25 461 →
// 221 s (its target 269). Its window's duty read round(L̂/8) bins back put A 1.9 % low on seed 2
// (the duty still rising after the landing); one bin less reads it within 0.4 %.
TEST(AutotuneSettledHold, DeadTimeFopdtHotendsSkipTheRelayAndKeepTheirModel) {
  std::vector<Plant> ps;
  for (const Plant& p : plants())
    if (in({"seed002", "seed004", "fopdt-120-25"}, p.name)) ps.push_back(p);
  ps.push_back(fopdt_plant("fopdt-30-25", 450, 30, 25));
  ps.push_back(fopdt_plant("fopdt-700-35-14", 700, 35, 14));
  for (const Plant& p : ps) {
    for (const unsigned long long seed : {12345ULL, 2ULL}) {
      const TuneRun r = run(p, 5, true, 0.1, false, 1.0, -1, false, 1800, seed);
      const control::HotendModel& m = r.result.model;
      std::printf("%-16s seed %5llu: %6.1f s, max − S %.2f °C, Tu %.2f, A %.1f C %.2f D %.2f F %.1f\n", p.name.c_str(), seed,
                  r.duration_s, r.max_c - p.target_c, q8(r.result.ultimate.tu_q8), q8(m.rise_q8),
                  q8(m.time_constant_q8), q8(m.dead_time_q8), q8(m.fan_loss_pct_q8));
      ASSERT_EQ(r.state, AutotuneState::kFinished) << p.name << " seed " << seed;
      EXPECT_EQ(r.cycles, 0) << p.name << " seed " << seed;  // no ` bias:` line
      EXPECT_EQ(r.result.ultimate.tu_q8, 0) << p.name << " seed " << seed;
      EXPECT_LE(r.duration_s, r.heatup_s + 180) << p.name << " seed " << seed;
      EXPECT_LE(r.max_c, p.target_c + 2.0) << p.name << " seed " << seed;
      EXPECT_NEAR(q8(m.rise_q8), p.k, 0.01 * p.k) << p.name << " seed " << seed;
      EXPECT_NEAR(q8(m.time_constant_q8), p.t, 0.02 * p.t) << p.name << " seed " << seed;
      EXPECT_NEAR(q8(m.dead_time_q8), p.l, 0.03 * p.l) << p.name << " seed " << seed;
      EXPECT_NEAR(q8(m.fan_loss_pct_q8), fan_pct(p.model, p.k), 0.05 * fan_pct(p.model, p.k)) << p.name << " seed " << seed;
    }
  }
}

// A dead time behind a thermistor lag (τ1/τ2/D): the cut probe reads its tail, whose FOPDT
// (τ1, the pulse's area for K, L from the tail's height) leads the deadbeat, and the landing
// holds, as on an FOPDT. Before, the probe's blunted peak and early decay (24/2/18.7: S 15.9 per
// bin for 19.2, T 38 s for 24) left the slow law crawling (218 s) and a relay (270 s): 570 s, up
// to S + 7 °C (24/8/20). D is the FOPDT the step response tends to: D + τ1·ln(τ1/(τ1 − τ2)).
TEST(AutotuneSettledHold, ADeadTimeBehindALagReadsItsTailAndSkipsTheRelay) {
  struct Case {
    double t1, t2, dead;
  };
  for (const Case& c : {Case{24, 2, 18.7}, Case{24, 1, 20}, Case{24, 4, 16}, Case{20, 2, 20}, Case{30, 3, 25}}) {
    const double d_eq = c.dead + c.t1 * std::log(c.t1 / (c.t1 - c.t2));
    const Plant p{"lag+dead", design::with_seed_fan(design::second_order(450, c.t1, c.t2, c.dead)), 210, 25, false, 450, c.t1, d_eq, c.t2, 0};
    // (Realisation 7 of 24/1/20 peaked sharp enough for an FOPDT's: its peak's S, 8 % low, led
    // the deadbeat to S + 10.3 °C before sharp peaks read their tail too.)
    for (const unsigned long long seed : {12345ULL, 2ULL, 7ULL}) {
      const TuneRun r = run(p, 5, true, 0.1, false, 1.0, -1, false, 1800, seed);
      const control::HotendModel& m = r.result.model;
      std::printf("%.0f/%.0f/%.1f s seed %5llu: %6.1f s (bound + 180: %.1f), max − S %.2f °C, A %.1f C %.2f D %.2f (%.2f) F %.1f\n",
                  c.t1, c.t2, c.dead, seed, r.duration_s, r.heatup_s + 180, r.max_c - p.target_c, q8(m.rise_q8),
                  q8(m.time_constant_q8), q8(m.dead_time_q8), d_eq, q8(m.fan_loss_pct_q8));
      ASSERT_EQ(r.state, AutotuneState::kFinished) << c.t2 << " seed " << seed;
      EXPECT_EQ(r.cycles, 0) << c.t2 << " seed " << seed;
      EXPECT_FALSE(r.lag_probe) << c.t2 << " seed " << seed;  // the tail's L̂ is a dead time
      EXPECT_EQ(r.overruns, 0) << c.t2 << " seed " << seed;
      // The bound + 3 min on the bank's seed002-lag2 (the first case); the others, not in
      // the bank, measured 173–253 s (30/3/25 up to bound + 29 s more: its hold waits out the window).
      EXPECT_LE(r.duration_s, r.heatup_s + (c.t2 == 2 && c.t1 == 24 ? 180 : 240)) << c.t2 << " seed " << seed;
      EXPECT_LE(r.max_c, p.target_c + 1.0) << c.t2 << " seed " << seed;
      EXPECT_NEAR(q8(m.rise_q8), p.k, 0.01 * p.k) << c.t2 << " seed " << seed;
      // (τ2 4 s still lifts the fourth window's tail: 24/4/16 read C up to 24.95 s.)
      EXPECT_NEAR(q8(m.time_constant_q8), c.t1, 0.05 * c.t1) << c.t2 << " seed " << seed;
      EXPECT_NEAR(q8(m.dead_time_q8), d_eq, 0.05 * d_eq) << c.t2 << " seed " << seed;
      EXPECT_NEAR(q8(m.fan_loss_pct_q8), fan_pct(p.model, p.k), 0.05 * fan_pct(p.model, p.k)) << c.t2 << " seed " << seed;
    }
  }
}

// Where the relay tells what the probe cannot, it stays: a tangent-timed flat probe whose dead time
// is short against C (fopdt-300-10: L̂ + 2 bins ≈ C/25), a thermistor lag (the two-node hotends, seed003,
// two-node-delay5), a short dead time (fopdt-60-3: L̂ + 2 bins < C/5, whose relay is short anyway), and a
// user who asks for more effort (C6 on seed002).
TEST(AutotuneSettledHold, TheRelayStaysWhereItTellsMore) {
  for (const Plant& p : plants()) {
    if (!in({"fopdt-300-10", "hotend40w", "seed003", "two-node-delay5", "fopdt-60-3", "seed002"}, p.name)) continue;
    const uint8_t cycles = p.name == "seed002" ? 6 : 5;
    const TuneRun r = run(p, cycles, true, 0.1, false, 1.0, -1, false, 1800);
    ASSERT_EQ(r.state, AutotuneState::kFinished) << p.name;
    EXPECT_GE(r.cycles, 2) << p.name;
    EXPECT_GT(r.result.ultimate.tu_q8, 0) << p.name;
  }
}

// A noisy sensor (Gaussian reading noise σ, as AUTOTUNE_NOISE): the probe's detection and peak,
// the relay's hysteresis and the trend guard scale with the noise the engine measures. Before,
// at σ 0.3 °C seed002 and fopdt-120-25 overshot by 15–17 °C (relay chatter) and seed000-4 ended
// at S + 24.6 °C (a creep taken for the response), at σ 0.5 both seed000 tunes at S + 24 °C.
TEST(AutotuneNoise, MeasuresTheReadingNoiseBeforeTheResponse) {
  // A hotend that does not respond (flat reading): baseline and probe both measure.
  for (const double sigma : {0.0, 0.1, 0.3, 0.5}) {
    design::PlantSim sim(design::fopdt(1e-6, 100, 1));  // no response to the heater
    sim.set_noise(sigma);
    Autotune at;
    at.configure(128);
    ASSERT_TRUE(at.start(210 * 256, 3, false));
    for (int i = 0; i < 30; ++i) at.step(static_cast<int32_t>(std::lround(sim.measured_c() * 256)));
    const double early = at.noise_q8() / 256.0;  // 16 readings, at the baseline's end
    for (int i = 0; i < 300; ++i) at.step(static_cast<int32_t>(std::lround(sim.measured_c() * 256)));
    const double later = at.noise_q8() / 256.0;
    std::printf("sigma %.1f: measured %.3f after 30 readings, %.3f after 330\n", sigma, early, later);
    EXPECT_NEAR(early, sigma, 0.3 * sigma + 0.01);  // 16 second differences
    EXPECT_NEAR(later, sigma, 0.15 * sigma + 0.01);  // σ 0.5: 9 % low by the 2 °C cap
  }
}

TEST(AutotuneNoise, EveryPlantFinishesWithinTargetPlus5AtSigma03) {
  // σ 0.3 °C, C3, on two noise realisations (the σ 0.5 bank below runs all eight).
  for (const unsigned long long seed : {2ULL, 3ULL}) {
    for (const Plant& p : plants()) {
      const TuneRun r = run(p, 3, true, 0.3, false, 1.0, -1, false, 1800, seed);
      EXPECT_LE(r.max_c, p.target_c + 5.0) << p.name << " seed " << seed;
      EXPECT_EQ(r.overruns, 0) << p.name;
      EXPECT_EQ(r.state, AutotuneState::kFinished) << p.name << " seed " << seed << " failure " << static_cast<int>(r.failure);
    }
  }
}

// The noisy bank: σ 0.5 °C (a noisy thermistor), M303's default C5, every plant over eight noise
// realisations (AUTOTUNE_SEED's 12345 and 1–7). Before the noise-proof relay nudge, the peak-based
// S and the tighter untrusted trend guard: 6 of these 120 runs above S + 5 °C (fopdt-120-25 6.8 /
// 5.9, seed000-4 5.9 / 5.9, seed000-5 6.3, seed002 5.2) and 2 failed (seed000-4: the relay stopped
// switching); now none above, and two still fail, safely below S + 5 (known misses,
// docs/autotune.md): seed000-5 on realisation 3 reaches the time limit (its untrusted approach
// and relay crawl on the trend guard), and on realisation 1 its relay stops switching, parked a
// degree above the target at its steady duty. (seed000-4 on realisation 4 stopped switching until
// an untrusted relay's halves had to last L̂/4 and its guard's dead band grew to 3σ/16.)
TEST(AutotuneNoise, NoisyBankAtSigma05StaysWithinTargetPlus5AndFinishes) {
  const std::set<std::string> known_fail = {"seed000-5/3", "seed000-5/1"};
  std::printf("%-16s %8s %8s\n", "plant", "max-S", "finished");
  for (const Plant& p : plants()) {
    double worst = -1e9;
    int finished = 0;
    for (const unsigned long long seed : {12345ULL, 1ULL, 2ULL, 3ULL, 4ULL, 5ULL, 6ULL, 7ULL}) {
      const TuneRun r = run(p, 5, true, 0.5, false, 1.0, -1, false, 1800, seed);
      worst = std::max(worst, r.max_c - p.target_c);
      if (r.state == AutotuneState::kFinished) ++finished;
      EXPECT_LE(r.max_c, p.target_c + 5.0) << p.name << " seed " << seed;
      EXPECT_EQ(r.overruns, 0) << p.name << " seed " << seed;
      if (!in(known_fail, p.name + "/" + std::to_string(seed))) {
        EXPECT_EQ(r.state, AutotuneState::kFinished) << p.name << " seed " << seed << " failure " << static_cast<int>(r.failure);
      }
    }
    std::printf("%-16s %8.2f %6d/8\n", p.name.c_str(), worst, finished);
  }
}

// seed000-4 at σ 0.2 °C: its untrusted approach's ū came out ~2 × the steady duty (S from a
// probe on a non-minimum-phase, lagging block), its loss learning never saw a steady duty, and
// the P law held the duty at ~0.3 while the reading climbed to S + 11.6 °C (realisation 7) and
// S + 9.8 (11). The approach now turns the heater off above the target while the trend guard
// sees the reading passing S + 2 °C: S + 4.6 and 3.9.
TEST(AutotuneNoise, Seed0004UntrustedApproachStopsHeatingAboveTheTarget) {
  for (const Plant& p : plants()) {
    if (p.name != "seed000-4") continue;
    for (const unsigned long long seed : {7ULL, 11ULL}) {
      const TuneRun r = run(p, 5, true, 0.2, false, 1.0, -1, false, 1800, seed);
      std::printf("seed000-4 σ 0.2 seed %llu: max − S %.2f °C, %.0f s\n", seed, r.max_c - p.target_c, r.duration_s);
      EXPECT_EQ(r.state, AutotuneState::kFinished) << "seed " << seed << " failure " << static_cast<int>(r.failure);
      EXPECT_LE(r.max_c, p.target_c + 5.0) << "seed " << seed;
    }
  }
}

// The relay's extremes and switch levels come from the 4-reading mean, which the noise lifts: the
// extremes outward (T read short) and the switches outward (λ = L/T read short). Before the
// lift was taken off, at σ 0.3 °C over 20 realisations 62 of the 120 FOPDT tunes had T beyond
// 10 % and 47 had D beyond 10 % (mean D −7 %); now 1 and 10 (mean +0.4 %). Here realisations
// 1–8: T within 10 %, D within 15 % (fopdt-30-1's D aside: 1 s, under the relay's resolution,
// and 2 of 20 realisations there take the lag-type rules: 1.4 s), the mean D error within 5 %,
// K within 1 %: since d is held over a cut probe's measured cycles K is within 0.8 % (was up to
// 2.0 %: fopdt-300-10 seed 2 459.2). (With d held alone that realisation's D read 8.42 s, was
// 8.79; its probe counts as lag-type, and with the re-learnt S 9.43. Worst D now 10.3 %.)
TEST(AutotuneNoise, FopdtTimeConstantAndDeadTimeOnANoisySensor) {
  double sum_d = 0;
  int n_d = 0;
  for (const Plant& p : plants()) {
    if (!p.fopdt) continue;
    for (unsigned long long seed = 1; seed <= 8; ++seed) {
      const TuneRun r = run(p, 5, true, 0.3, false, 1.0, -1, false, 1800, seed);
      ASSERT_EQ(r.state, AutotuneState::kFinished) << p.name << " seed " << seed;
      const control::HotendModel& m = r.result.model;
      EXPECT_NEAR(q8(m.time_constant_q8), p.t, 0.10 * p.t) << p.name << " seed " << seed;
      EXPECT_NEAR(q8(m.rise_q8), p.k, 0.01 * p.k) << p.name << " seed " << seed;
      if (p.name == "fopdt-30-1") continue;
      EXPECT_NEAR(q8(m.dead_time_q8), p.l, 0.15 * p.l) << p.name << " seed " << seed;
      sum_d += (q8(m.dead_time_q8) - p.l) / p.l;
      ++n_d;
    }
  }
  std::printf("mean D error over %d tunes: %+.1f %%\n", n_d, 100 * sum_d / n_d);
  EXPECT_NEAR(sum_d / n_d, 0.0, 0.05);
}

// At σ 0.5 °C a trusted relay's halves of L̂/2 ended on noise crossings on dead-time hotends:
// cycles of about L̂ instead of ~3 L̂, and D read 35–60 % short on these 7 of the 120 FOPDT tunes
// over realisations 1–20 (seed004 3, 8, 20; seed002 4; fopdt-120-25 13, 15, 17: −60, −35, −60,
// −60, −57, −55, −59 %). With halves of at least L̂ there (noise above 0.3 °C, L̂/T ≥ 0.2):
// +6, −23, −6, +7, −12, −3, −2 %. Each within 30 %, and none peaks higher than before.
TEST(AutotuneNoise, DeadTimeRelayIgnoresNoiseCrossingsAtSigma05) {
  struct Case { const char* plant; unsigned long long seed; };
  const std::vector<Plant> ps = plants();
  for (const Case c : {Case{"seed004", 3}, Case{"seed004", 8}, Case{"seed004", 20}, Case{"seed002", 4},
                       Case{"fopdt-120-25", 13}, Case{"fopdt-120-25", 15}, Case{"fopdt-120-25", 17}}) {
    const Plant* p = nullptr;
    for (const Plant& q : ps)
      if (q.name == c.plant) p = &q;
    ASSERT_NE(p, nullptr) << c.plant;
    const TuneRun r = run(*p, 5, true, 0.5, false, 1.0, -1, false, 1800, c.seed);
    ASSERT_EQ(r.state, AutotuneState::kFinished) << c.plant << " seed " << c.seed;
    const double d = q8(r.result.model.dead_time_q8);
    std::printf("%s σ 0.5 seed %llu: D %.2f s (true %.2f)\n", c.plant, c.seed, d, p->l);
    EXPECT_NEAR(d, p->l, 0.30 * p->l) << c.plant << " seed " << c.seed;
    // A half whose mean is 2 °C past the target may end after L̂/2 as before: seed004
    // realisation 8's relay, both levels above the steady duty, peaked at S + 6.44 °C with every
    // half ≥ L̂; 5.33 as before with it (above S + 5 already before this rule: docs/autotune.md).
    EXPECT_LE(r.max_c, p->target_c + 5.8) << c.plant << " seed " << c.seed;
  }
}

// heavy-slow (untrusted: its 25 s sensor lag outlasts the model history) on the noise
// realisations where its relay stopped switching ("no oscillation") before three changes: the
// first half's stall test measured progress from a stale reference (0 °C) so it never fired; a
// noise crossing 1 s after a switch ended a half and the cycle's bias then sat 10 % below the
// steady duty (an untrusted relay's halves now last ≥ L̂/4); and the trend guard's false alarms
// at a 2σ/16 dead band cut more heat than the relay's d added (3σ/16 now).
TEST(AutotuneNoise, HeavySlowRelayKeepsSwitchingOnANoisySensor) {
  const Plant* heavy = nullptr;
  const std::vector<Plant> ps = plants();
  for (const Plant& p : ps)
    if (p.name == "heavy-slow") heavy = &p;
  ASSERT_NE(heavy, nullptr);
  struct Case { double noise; unsigned long long seed; };
  for (const Case c : {Case{0.3, 9}, Case{0.3, 18}, Case{0.3, 19}, Case{0.5, 9}, Case{0.5, 12}, Case{0.5, 18},
                       Case{0.5, 19}, Case{0.5, 12345}}) {
    const TuneRun r = run(*heavy, 5, true, c.noise, false, 1.0, -1, false, 1800, c.seed);
    EXPECT_EQ(r.state, AutotuneState::kFinished) << "σ " << c.noise << " seed " << c.seed << " failure "
                                                 << static_cast<int>(r.failure);
    EXPECT_LE(r.max_c, heavy->target_c + 5.0) << "σ " << c.noise << " seed " << c.seed;
  }
}

// A cold probe that needed a longer pulse (nothing in a minute after the first) on a noisy sensor
// (σ 0.5 °C, the realisations where it went wrong): a noise dip passed for the retry's peak 20 s
// after its cut (seed000's true response takes ~250 s), the model was trusted, and its predictor
// heated seed000-4 to S + 24.2 °C (the S + 25 abort) and seed000-5 to S + 20.3 °C. Such a model
// is now untrusted, with the trend guard's longest horizon. (Finishing is not asserted: with L̂
// that short the time limit hardly grows, so seed000-4 ends by the time limit, at S + 3.5 °C.)
TEST(AutotuneNoise, ARetriedProbeOnANoisySensorIsNotTrusted) {
  for (const Plant& p : plants()) {
    const unsigned long long seed = p.name == "seed000-4" ? 15 : (p.name == "seed000-5" ? 14 : 0);
    if (seed == 0) continue;
    const TuneRun r = run(p, 5, true, 0.5, false, 1.0, -1, false, 1800, seed);
    EXPECT_LE(r.max_c, p.target_c + 5.0) << p.name;
    EXPECT_NE(r.failure, AutotuneFailure::kTooHot) << p.name;
  }
}

// The loss learnt at full power (Δslope/Δrise between a reference 4-bin slope and the latest):
// taken as the latest estimate, one slope's noise at σ 0.3 °C read fopdt-120-25's 1/T 24 % high
// on this realisation, its steady duty 20 % high, and the slow approach law held it at S + 9.5 °C.
// Later estimates now move the first by ¼ each.
TEST(AutotuneNoise, LossLearntAtFullPowerAveragesTheSlopesNoise) {
  for (const Plant& p : plants()) {
    if (p.name != "fopdt-120-25") continue;
    const TuneRun r = run(p, 5, true, 0.3, false, 1.0, -1, false, 1800, 14);
    EXPECT_EQ(r.state, AutotuneState::kFinished);
    EXPECT_LE(r.max_c, p.target_c + 5.0);
  }
}

TEST(Autotune, HotStartsAndStartsAboveTheTarget) {
  const std::vector<Plant> ps = plants();
  struct Case { size_t plant; double start, target; };
  for (const Case c : {Case{0, 200, 240}, Case{0, 230, 210}, Case{1, 200, 240}, Case{4, 200, 240}, Case{2, 229, 210}}) {
    Plant p = ps[c.plant];
    p.target_c = c.target;
    const TuneRun r = run(p, 3, true, 0.1, false, 1.0, c.start);
    std::printf("%-12s %3.0f -> %3.0f °C: %6.1f s (full-power heat-up %5.1f s), max %+5.2f, K %6.1f T %6.1f L %5.2f F %5.1f\n",
                p.name.c_str(), c.start, c.target, r.duration_s, r.heatup_s, r.max_c - p.target_c, q8(r.result.model.rise_q8),
                q8(r.result.model.time_constant_q8), q8(r.result.model.dead_time_q8), q8(r.result.model.fan_loss_pct_q8));
    EXPECT_EQ(r.state, AutotuneState::kFinished) << p.name << " from " << c.start;
    EXPECT_LE(r.max_c, c.target + 5.0) << p.name << " from " << c.start;
    EXPECT_TRUE(r.result.hot_start);
    EXPECT_NEAR(q8(r.result.model.rise_q8), p.k, 0.10 * p.k) << p.name << " from " << c.start;
    // The time constant: from the loss the approach learnt where the relay's FOPDT formulas read
    // a sensor lag as a long T (hotend40w 683 / 713 s against 245.6: now 261 / 339 s; a start
    // above the target learns its loss less well). 339 s was this realisation's; others read
    // 349 s with or without the hot start's trend guard (which this one now takes: its pulse
    // read 1.5 × low), so 45 % (349 s is +42 %). The relay's own on FOPDT plants.
    EXPECT_NEAR(q8(r.result.model.time_constant_q8), p.t, (c.start > c.target ? 0.45 : 0.15) * p.t)
        << p.name << " from " << c.start;
  }
}

TEST(Autotune, AbortsAboveTargetPlus25WithTheHeaterOff) {
  // A heater that stays on whatever the tune says (failed MOSFET): the tune must give up at
  // S + 25 °C, say so, and command 0.
  const Plant p = plants()[0];
  const TuneRun r = run(p, 3, true, 0.1, false, 1.0, -1, true);
  EXPECT_EQ(r.state, AutotuneState::kFailed);
  EXPECT_EQ(r.failure, AutotuneFailure::kTooHot);
  EXPECT_LT(r.max_c, p.target_c + 25.5);
  Autotune at;
  at.configure(128);
  ASSERT_TRUE(at.start(200 * 256, 3, false));
  const control::AutotuneOutput out = at.step((225 * 256) + 1);
  EXPECT_EQ(out.duty_q16, 0);
  EXPECT_EQ(out.state, AutotuneState::kFailed);
  EXPECT_EQ(out.failure, AutotuneFailure::kTooHot);
  EXPECT_EQ(at.step(100 * 256).duty_q16, 0);  // stays off
}

TEST(Autotune, DeadHeaterIsNoHeating) {
  const TuneRun r = run(plants()[0], 3, true, 0.1, false, 0.0);
  EXPECT_EQ(r.state, AutotuneState::kFailed);
  EXPECT_EQ(r.failure, AutotuneFailure::kNoHeating);
  EXPECT_LT(r.duration_s, 600);  // 4 pulses, each ×4 longer, and a minute's wait after each
}

TEST(Autotune, TimesOutAtTheLimitGrownByTheMeasuredResponseTime) {
  // 60 s configured: the probe (≈ 20 s) measures L̂ ≈ 3.7 s, and (8 + 2 for the fan hold + 4) ×
  // 6 L̂ ≈ 310 s after it is longer, capped at 4 × 60 s: the C8 tune, which needs ≈ 275 s, times
  // out there (C3's ≈ 212 s now fits in the grown limit).
  const TuneRun r = run(plants()[0], 8, true, 0.1, false, 1.0, -1, false, 60);
  EXPECT_EQ(r.state, AutotuneState::kFailed);
  EXPECT_EQ(r.failure, AutotuneFailure::kTimeout);
  EXPECT_GT(r.duration_s, 200);
  EXPECT_LE(r.duration_s, 240.2);
  // A heater too weak to reach the target (a stuck tune) still ends, by the firmware's 30 min
  // grown to at most 2 h.
  const TuneRun weak = run(plants()[0], 5, true, 0.1, false, 0.3);
  EXPECT_EQ(weak.state, AutotuneState::kFailed);
  EXPECT_LE(weak.duration_s, 7200.2);
}

TEST(Autotune, AbortAndBadParameters) {
  Autotune at;
  at.configure(128);
  EXPECT_FALSE(at.start(210 * 256, 2, true));
  EXPECT_EQ(at.failure(), AutotuneFailure::kBadParameters);
  EXPECT_FALSE(at.start(210 * 256, 21, true));
  EXPECT_FALSE(at.start(300 * 256, 5, true));
  ASSERT_TRUE(at.start(210 * 256, 5, true));
  EXPECT_EQ(at.state(), AutotuneState::kRunning);
  for (int i = 0; i < 100; ++i) at.step(25 * 256);
  at.abort();
  EXPECT_EQ(at.state(), AutotuneState::kFailed);
  EXPECT_EQ(at.failure(), AutotuneFailure::kAborted);
  const control::AutotuneOutput out = at.step(25 * 256);
  EXPECT_EQ(out.duty_q16, 0);
  EXPECT_EQ(out.fan_duty, 0);
}

TEST(Autotune, ReportsMarlinCycleLinesAndKuTu) {
  // hotend40w: every relay cycle gives bias/d on the 0..255 scale and min/max around the
  // target; Ku = 4d/(πa) and Tu = the period match the cycle's own figures.
  design::PlantSim sim(design::two_node());
  sim.set_noise(0.1);
  Autotune at;
  at.configure(128);
  ASSERT_TRUE(at.start(210 * 256, 3, false));
  int cycles = 0;
  for (int i = 0; i < 20000 && at.state() == AutotuneState::kRunning; ++i) {
    const control::AutotuneOutput out = at.step(static_cast<int32_t>(std::lround(sim.measured_c() * 256)));
    if (out.event == control::AutotuneEvent::kCycle || out.event == control::AutotuneEvent::kUltimate) {
      ++cycles;
      const control::AutotuneCycle& c = at.cycle();
      std::printf(" bias: %d d: %d min: %.2f max: %.2f", c.bias, c.d, q8(c.min_q8), q8(c.max_q8));
      if (out.event == control::AutotuneEvent::kUltimate)
        std::printf(" Ku: %.2f Tu: %.2f", q8(at.ultimate().ku_q8), q8(at.ultimate().tu_q8));
      std::printf("\n");
      EXPECT_GT(c.bias, 40);
      EXPECT_LT(c.bias, 120);  // ~31 % of 255 = 80
      EXPECT_GE(c.d, 1);
      EXPECT_LT(q8(c.min_q8), 210.0);
      EXPECT_GT(q8(c.max_q8), 210.0);
      EXPECT_LT(q8(c.max_q8) - q8(c.min_q8), 8.0);
      const double a = (q8(c.max_q8) - q8(c.min_q8)) / 2;
      EXPECT_NEAR(q8(at.ultimate().ku_q8), 4.0 * c.d / (3.14159265 * a), 0.05 * 4.0 * c.d / (3.14159265 * a) + 0.5);
    }
    sim.set_fan(out.fan_duty / 255.0);
    sim.run(out.duty_q16 / 65535.0, kPeriodS);
  }
  EXPECT_EQ(at.state(), AutotuneState::kFinished);
  // C3: two measured cycles; the approach settles on the target, so no settling cycle before.
  EXPECT_EQ(cycles, 2);
  EXPECT_GT(q8(at.result().ultimate.tu_q8), 5.0);
  EXPECT_FALSE(at.result().hot_start);
  EXPECT_NEAR(q8(at.result().ambient_q8), 25.0, 0.1);
}

// The fan step's window is ⌈C/2⌉ × (L̂/2 + 4) bins after L̂ + 2: a long horizon with C20 (163 bins
// on fopdt-120-25) must still end (the former hold's 8-bit count once wrapped) and read F.
TEST(Autotune, FanStepAtItsLongestStillEnds) {
  for (const Plant& p : plants()) {
    if (p.name != "fopdt-120-25") continue;
    const TuneRun r = run(p, 20, true, 0.1, false, 1.0, -1, false, 1800);  // the firmware's limit
    EXPECT_EQ(r.state, AutotuneState::kFinished) << "failure " << static_cast<int>(r.failure);
    EXPECT_NEAR(q8(r.result.model.fan_loss_pct_q8), fan_pct(p.model, p.k), 0.20 * fan_pct(p.model, p.k));
  }
}

// The fan part (F1) is an open-loop step: fan 100 %, the heater held at the last relay cycle's
// mean duty, F read from the reading's level and fall once the dead time has passed. On the
// dead-time plants it lasts 1.3–1.7 dead times at C5 (the closed-loop hold before: 180–270 s,
// 8–10 L: the approach law's recovery from the dip, then ⌈C/2⌉ × (L̂ + 2) bins), one duty, F
// within 20 %.
TEST(Autotune, FanStepHoldsOneDutyForAFewDeadTimes) {
  for (const Plant& p : plants()) {
    if (p.name != "seed002" && p.name != "seed004") continue;
    design::PlantSim sim(p.model);
    sim.set_noise(0.1);
    Autotune at;
    at.configure(128, 1800);
    ASSERT_TRUE(at.start(static_cast<int32_t>(std::lround(p.target_c * 256)), 5, true));
    double fan_on_s = -1, fan_off_s = -1;
    uint16_t duty_min = 65535, duty_max = 0;
    for (int i = 0; i < 40000 && at.state() == AutotuneState::kRunning; ++i) {
      const control::AutotuneOutput out = at.step(static_cast<int32_t>(std::lround(sim.measured_c() * 256)));
      if (out.fan_duty > 0) {
        if (fan_on_s < 0) fan_on_s = sim.time_s();
        duty_min = std::min(duty_min, out.duty_q16);
        duty_max = std::max(duty_max, out.duty_q16);
      } else if (fan_on_s >= 0 && fan_off_s < 0) {
        fan_off_s = sim.time_s();
      }
      sim.set_fan(out.fan_duty / 255.0);
      sim.run(out.duty_q16 / 65535.0, kPeriodS);
    }
    ASSERT_EQ(at.state(), AutotuneState::kFinished) << p.name;
    ASSERT_GT(fan_on_s, 0) << p.name;
    const double fan_s = fan_off_s - fan_on_s;
    std::printf("%-14s fan part %5.1f s (%.2f L), duty %.3f, F %.1f %% (true %.1f)\n", p.name.c_str(), fan_s, fan_s / p.l,
                duty_max / 65535.0, q8(at.result().model.fan_loss_pct_q8), fan_pct(p.model, p.k));
    EXPECT_LE(fan_s, 2.0 * p.l) << p.name;
    EXPECT_EQ(duty_min, duty_max) << p.name;  // open loop: one duty throughout
    EXPECT_NEAR(q8(at.result().model.fan_loss_pct_q8), fan_pct(p.model, p.k), 0.20 * fan_pct(p.model, p.k)) << p.name;
  }
}

// Without the fan (F0) the relay's gain gets the same drift correction as with it (the relay runs
// the same up to the fan): light-fast's two measured cycles of a slow mode read K 7.6 % high
// without it, 4.5 % with it.
TEST(Autotune, RelayDriftCorrectedWithoutTheFan) {
  for (const Plant& p : plants()) {
    if (p.name != "light-fast") continue;
    const TuneRun with_fan = run(p, 3, true);
    const TuneRun no_fan = run(p, 3, false);
    ASSERT_EQ(with_fan.state, AutotuneState::kFinished);
    ASSERT_EQ(no_fan.state, AutotuneState::kFinished);
    std::printf("light-fast K: fan %.1f, F0 %.1f, true %.1f\n", q8(with_fan.result.model.rise_q8),
                q8(no_fan.result.model.rise_q8), p.k);
    EXPECT_EQ(no_fan.result.model.rise_q8, with_fan.result.model.rise_q8);
    EXPECT_NEAR(q8(no_fan.result.model.rise_q8), p.k, 0.06 * p.k);
  }
}

// Two lags of comparable size (seed003's 28.3 and 14.2 s, and two more ratios): the probe hands
// over before the heat-up's inflection, where the tangent's (K − y)/S reads τ1 + τ2 long by
// τ1·τ2·ÿ/ẏ (seed003: 48 s against 42.5), and with it the fan step's F (52 % against 42.6), and
// relay cycles whose d changed read K 2.2 % high (the lags carry the new d's transient across the
// cycles' ends). The fit of K·t − ∫y = Σ·y + Π·ẏ at two heat-up points and a d held over the
// measured cycles: F within 10 % of the plant's (60/30 reads 38.5–39 %: its fan window ends
// before the fall's own inflection), K within 1.5 %, and C = Σ − the tangent's dead time shorter
// than Σ (seed003's old figures, K 459.8, C 43.0, F 52.0 %, fail all three).
TEST(Autotune, TwoLagHotendsReadTheLagSumAndTheFanLoss) {
  struct Lags {
    double t1, t2;
  };
  for (const Lags l : {Lags{0.64 * 44.2696, 0.32 * 44.2696}, Lags{40, 10}, Lags{60, 30}}) {
    const design::LtiModel m = design::with_seed_fan(design::second_order(450, l.t1, l.t2));
    const Plant p{"two-lag", m, 210, 25, false, 450, l.t1, 0, l.t2, 0};
    for (unsigned long long seed : {12345ULL, 1ULL, 2ULL}) {
      const TuneRun r = run(p, 5, true, 0.1, false, 1.0, -1, false, 3600, seed);
      ASSERT_EQ(r.state, AutotuneState::kFinished) << l.t1 << "/" << l.t2;
      const control::HotendModel& h = r.result.model;
      std::printf("two lags %.1f/%.1f seed %llu: K %.1f C %.2f (Σ %.1f) D %.2f F %.1f (true %.1f)\n", l.t1, l.t2, seed,
                  q8(h.rise_q8), q8(h.time_constant_q8), l.t1 + l.t2, q8(h.dead_time_q8), q8(h.fan_loss_pct_q8),
                  fan_pct(m, 450));
      EXPECT_NEAR(q8(h.rise_q8), 450, 0.015 * 450) << l.t1 << "/" << l.t2 << " seed " << seed;
      EXPECT_NEAR(q8(h.fan_loss_pct_q8), fan_pct(m, 450), 0.10 * fan_pct(m, 450)) << l.t1 << "/" << l.t2 << " seed " << seed;
      EXPECT_LT(q8(h.time_constant_q8), l.t1 + l.t2) << l.t1 << "/" << l.t2 << " seed " << seed;
    }
  }
}

}  // namespace

// A light 80 W block (6 J/K, 1 s sensor lag) behind a 20 s transport delay: its cut probe peaks
// flat with an FOPDT's timing (cut-to-peak ≈ pulse-to-response). A deadbeat approach allowed on
// such flat peaks landed it at S + 3.6 °C with the relay biased above its steady duty; it then
// climbed to S + 25 °C and aborted in 6 of 9 runs (σ 0.1–0.5 × 3 noise seeds). The deadbeat now
// needs a sharp peak; the slow law brings this block in within S + 1.6 °C.
TEST(Autotune, FlatPeakBehindATransportDelayStaysWithinTargetPlus5) {
  design::TwoNodeParams p;
  p.block_j_per_k = 6;
  p.heater_w = 80;
  p.sensor_rate_per_s = 1.0;
  const Plant plant = two_node_plant("light-80W-delay20", p, 210, 20.0);
  for (double noise : {0.1, 0.3, 0.5}) {
    for (unsigned long long seed : {12345ULL, 1ULL, 2ULL}) {
      const TuneRun r = run(plant, 5, true, noise, false, 1.0, -1, false, 1800, seed);
      EXPECT_EQ(r.state, AutotuneState::kFinished) << "σ " << noise << " seed " << seed << " failure "
                                                   << static_cast<int>(r.failure);
      EXPECT_LE(r.max_c, plant.target_c + 5.0) << "σ " << noise << " seed " << seed;
    }
  }
}

// A part fan that does not cool the nozzle (no fan, or a shroud aimed elsewhere), F1 the default:
// the fan step holds the last relay cycle's mean duty open loop, and that mean can sit above the
// steady duty, so the reading may rise instead of fall. The step ends once it is 2 °C above S;
// before, seed000-4 reached S + 9.1 °C and two-node-30W at C20 S + 5.8 °C (σ 0.3). F then reads
// 0–14 %, except on the unsure seed000 plants at C5: seed000-4 59 %, seed000-5 31 % (their
// relay's last mean duty sits off the steady one and the slow fall passes for the fan's; they
// read 12 % / 230 % until the noisy relay's fixes changed which cycle is last: chance, so not
// asserted there; at C20 both read 4–5 %).
TEST(Autotune, FanThatDoesNotCoolEndsTheStepBeforeTargetPlus5) {
  for (Plant p : plants()) {
    p.model.fan_loss_per_k = 0;
    for (uint8_t cycles : {uint8_t{5}, uint8_t{20}}) {
      const TuneRun r = run(p, cycles, true, 0.3, false, 1.0, -1, false, 3600);
      if (r.state != AutotuneState::kFinished) continue;  // the noisy bank's known failures (AutotuneNoise)
      EXPECT_LE(r.max_c, p.target_c + 5.0) << p.name << " C" << int{cycles};
      if (p.name.compare(0, 7, "seed000") != 0) {
        EXPECT_LT(q8(r.result.model.fan_loss_pct_q8), 15.0) << p.name << " C" << int{cycles};
      }
    }
  }
}

// Steps a started tune at 128 ms on a lag_delay_hotend, as autotune_fuzz does, until it ends (at
// most 80,000 periods); returns its last output and the highest reading in *max_c.
control::AutotuneOutput tune_lag_delay_hotend(Autotune& at, const lag_delay_hotend::Params& p, double* max_c) {
  lag_delay_hotend::Hotend hotend(p, kPeriodS);
  control::AutotuneOutput o{};
  *max_c = -1e9;
  for (int i = 0; i < 80000; ++i) {
    const double y = hotend.reading();
    *max_c = std::fmax(*max_c, y);
    o = at.step(static_cast<int32_t>(std::lround(y * 256)));
    if (o.state != AutotuneState::kRunning) break;
    hotend.run(o.duty_q16 / 65535.0, o.fan_duty / 255.0);
  }
  return o;
}

// autotune_fuzz's findings: tunes whose relay cycles all miss the FOPDT formulas (no relay T)
// finished with C = 0, a model M307 refuses, though the probe had one; the probe's C, else K/S,
// now stands in. (a) a lag-heavy hotend (two lags 290 s and 25 s) on a quantised sensor (0.2 °C
// steps, σ 0.1 °C): its low level's steady rise sits above the cycle's minimum, the probe's C
// serves; (b) a very slow block (τ 2,497 s) tuned at 70 °C, C11: no probe C (its peak never
// shows), K/S serves. Before: C 0 on both.
struct NoRelayTCase {
  const char* name;
  lag_delay_hotend::Params plant;
  int32_t target_c;
  uint8_t cycles;
  double c_low_s, c_high_s;  // the time constant accepted (the plant's own FOPDT lies within)
  bool designs;  // U1 designs on it (the slow block's PID rule wants a Kp over Pid's limit: refused)
};

TEST(Autotune, NoFopdtRelayCycleStillGivesATimeConstant) {
  lag_delay_hotend::Params lag_heavy;
  lag_heavy.k_c = 430;
  lag_heavy.tau1_s = 289.8;
  lag_heavy.tau2_s = 25.2;
  lag_heavy.dead_s = 1.2;
  lag_heavy.noise_c = 0.1;
  lag_heavy.quant_c = 0.2;
  lag_heavy.noise_seed = 4;
  lag_delay_hotend::Params slow;
  slow.k_c = 454;
  slow.tau1_s = 2497.4;
  slow.fan_loss = 0;
  slow.ambient_c = 15;
  const NoRelayTCase cases[] = {{"lag-heavy, quantised", lag_heavy, 210, 5, 0.5 * 289.8, 1.5 * 289.8, true},
                                {"slow block at 70 °C", slow, 70, 11, 0.9 * 2497.4, 1.1 * 2497.4, false}};
  for (const NoRelayTCase& c : cases) {
    Autotune at;
    at.configure(128);
    ASSERT_TRUE(at.start(c.target_c * 256, c.cycles, true)) << c.name;
    double max_c = 0;
    const control::AutotuneOutput o = tune_lag_delay_hotend(at, c.plant, &max_c);
    ASSERT_EQ(o.state, AutotuneState::kFinished) << c.name;
    const control::HotendModel& m = at.result().model;
    std::printf("  %s: A %.1f C %.1f D %.1f F %.1f (plant %.0f, τ1 %.1f s)\n", c.name, m.rise_q8 / 256.0,
                m.time_constant_q8 / 256.0, m.dead_time_q8 / 256.0, m.fan_loss_pct_q8 / 256.0, c.plant.k_c, c.plant.tau1_s);
    EXPECT_NEAR(m.rise_q8 / 256.0, c.plant.k_c, c.plant.k_c * 0.05) << c.name;
    EXPECT_GT(m.time_constant_q8 / 256.0, c.c_low_s) << c.name;
    EXPECT_LT(m.time_constant_q8 / 256.0, c.c_high_s) << c.name;
    EXPECT_TRUE(control::hotend_model_valid(m)) << c.name;  // what M307 accepts
    control::TunedDesign d;
    EXPECT_EQ(control::design_from_tune(at.result(), 128, &d), c.designs) << c.name;
  }
}

// Hotends from autotune_fuzz's envelope search (AUTOTUNE_FUZZ_ENVELOPE=1, the parameters as it
// draws them from its bytes, named by their first three), tuned by the engine at 128 ms as the
// fuzzer does; each must finish within S + 5 °C.
struct EnvelopeCase {
  const char* name;
  lag_delay_hotend::Params plant;  // K, τ1, τ2, delay, fan loss, σ, ADC step, ambient, start rise, seed
  int32_t target_q8;
  uint8_t cycles;
  bool fan;
};

void expect_envelope_tune(const EnvelopeCase& c) {
  const lag_delay_hotend::Params& p = c.plant;
  Autotune at;
  at.configure(128);
  ASSERT_TRUE(at.start(c.target_q8, c.cycles, c.fan)) << c.name;
  double max_c = 0;
  const control::AutotuneOutput o = tune_lag_delay_hotend(at, p, &max_c);
  const double target_c = c.target_q8 / 256.0;
  std::printf("  %s (K %.0f, τ1 %.1f s, τ2 %.1f s, D %.1f s, σ %.2f °C, S %.0f): %s, max S %+.2f °C, %.0f s\n", c.name,
              p.k_c, p.tau1_s, p.tau2_s, p.dead_s, p.noise_c, target_c,
              o.state == AutotuneState::kFinished ? "finished" : "failed", max_c - target_c,
              at.elapsed_ticks() * kPeriodS);
  EXPECT_EQ(o.state, AutotuneState::kFinished) << c.name;
  EXPECT_LE(max_c, target_c + 5.0) << c.name;
}

// A cut probe on a lag-type hotend (a 5–17 s sensor lag and a few seconds of dead time) read
// through σ 0.17–0.25 °C noise ran its approach on the cut-to-peak time L̂, as on a dead-time
// hotend, and its P law parked 6–16 °C above S; on a quiet sensor the lag rule (D + τ2) served.
// It now serves up to a measured σ of 0.35 °C.
TEST(Autotune, LagTypeHotendOnANoisySensorApproachesOnItsLag) {
  const EnvelopeCase cases[] = {
      {"7b5134", {782.353, 62.3138, 17.4294, 4.46468, 0.554118, 0.176471, 0.151765, 34.1373, 0, 20}, 43776, 19, true},
      {"997467", {900, 85.4593, 10.1894, 6.90468, 0.570588, 0.244706, 0.141176, 23.549, 0, 200}, 52420, 4, true},
      {"c7821c", {1080.39, 96.9682, 15.0496, 1.85633, 0.130588, 0.222353, 0.183529, 31.6275, 0, 109}, 63277, 20, true},
      {"3c1540", {535.294, 36.2599, 14.3547, 4.80997, 0.274118, 0.252941, 0.134118, 25.7451, 0, 37}, 43038, 3, false},
      {"562846", {637.255, 43.0421, 11.3091, 4.27912, 0.587059, 0.22, 0.297647, 17.5882, 0, 137}, 63488, 6, false},
      {"a08681", {927.451, 100.532, 7.74893, 7.93343, 0.685882, 0.249412, 0.00705882, 26.7647, 0, 220}, 54001, 9, false},
      {"dc6f8e", {1162.75, 81.6888, 8.03382, 10.0956, 0.695294, 0.169412, 0.154118, 21.902, 0, 203}, 46095, 3, true},
      // σ 0.28 °C and a 0.28 °C ADC step: the estimate read σ 0.30 (S + 8.4 °C at a 0.3 °C limit)
      {"6cae6d", {723.529412, 144.237487, 8.70948097, 6.50228374, 0.443529412, 0.28, 0.28, 23.3921569, 0, 37}, 58639, 9, false}};
  for (const EnvelopeCase& c : cases) expect_envelope_tune(c);
}

// A strong heater (8.7–14.6 °C/s) behind an 18–25 s sensor lag: the probe heated on past its cap
// while the slope still rose, its horizon (2 × the detection time + 4 s) blind to the heat in
// flight, and handed over to the tangent path; the reading then went to S + 22–25 °C (two of the
// three ended at the S + 25 °C abort). The probe now cuts once the heat in flight (measured, or at
// 20 °C/s while unmeasurable) would carry the reading near the target.
TEST(Autotune, StrongHeaterBehindALongSensorLagCutsItsProbe) {
  const EnvelopeCase cases[] = {
      {"ffb200", {1300, 149.539291, 25, 0, 0.335294118, 0.0494117647, 0.0470588235, 25.0392157, 0, 7}, 51893, 5, true},
      {"998500", {900, 99.6293177, 25, 0, 0.335294118, 0.249411765, 0.0470588235, 25.0392157, 0, 7}, 51893, 5, true},
      {"fb770e", {1284.31373, 87.8045581, 18.0235755, 1.04701269, 0.172941176, 0.247058824, 0.0505882353, 24.9607843, 0, 20}, 62856, 9, true}};
  for (const EnvelopeCase& c : cases) expect_envelope_tune(c);
}

// A probe that handed over to the tangent path on a 16–20 s sensor lag (the slope looked steady):
// the tangent's dead time (8.5 bins on the first) fell short of the lag, the approach's
// predictor took too little heat for in flight, and the relay went to S + 13..18 °C. The approach
// now also takes the lag the heat-up measured (τ·ẏ) where it is over 1.5 × the tangent's.
TEST(Autotune, ContinuousProbeApproachesOnTheMeasuredLag) {
  const EnvelopeCase cases[] = {
      {"99b200", {900, 149.539291, 20.0117647, 0, 0.335294118, 0.0494117647, 0.0470588235, 25.0392157, 0, 7}, 51893, 5, true},
      {"cf9b01", {1111.76471, 121.50988, 15.7146021, 0.0618685121, 0.631764706, 0.112941176, 0.0105882353, 28.3333333, 0, 80}, 54212, 6, false}};
  for (const EnvelopeCase& c : cases) expect_envelope_tune(c);
}

// A tangent probe whose loss is learnt near the target only learns it at ¼ per bin, unblocked by
// its own ū steps. On a 15 s sensor lag under 1.5 × the tangent's dead time (11.2 against 7.5
// bins) that learning alone raised ū while the lag still held heat back, and the approach went to
// S + 5.5 °C (the slower ⅛ learning before it stayed within S + 3 °C). So the approach also takes
// the heat in flight behind any measured lag until the loss is learnt at full power; this guards
// the pair (envelope survey grid, 66850095…).
TEST(Autotune, LossLearntNearTheTargetApproachesOnAnyMeasuredLag) {
  expect_envelope_tune({"668500", {700, 99.6293177, 15.0235294, 0, 0.335294118, 0.0494117647, 0.0470588235, 25.0392157, 0, 7}, 65280, 5, true});
}

// An approach that held the target with the heater off (its loss never learnt, ū = 0) started the
// relay at a bias of 0.2 %, under the smallest d: the low level bias − d wrapped to 99.7 %, and
// the relay's first (low) half heated from S to the S + 25 °C abort.
TEST(Autotune, RelayLowLevelNeverWrapsToFullPower) {
  expect_envelope_tune({"ffff00", {1300, 299.599332, 10.0352941, 0, 0.335294118, 0.0494117647, 0.0470588235, 25.0392157, 0, 7}, 51893, 5, true});
}

// The same start (the approach held the target with the heater off, so the relay's bias said
// nothing: levels 0 and 2d) on a strong heater behind a 21 s lag: the reading fell from S to
// S − 120 °C while the 2d limit moved the bias 1 % a nudge, and the relay ended `did not hold`
// (envelope survey grid, ff8526…). Its first nudge now sets levels 0 and the fall's ū.
TEST(Autotune, RelayWithNoBiasTakesTheLossFromItsFirstFall) {
  expect_envelope_tune({"ff8526", {1300, 99.6293177, 21.2745098, 3.7254902, 0.335294118, 0.0494117647, 0.0470588235, 25.0392157, 0, 7}, 51893, 5, true});
}

// From a standby temperature (a start script's M104 S150 before the tune: the hotend held 60 °C
// below the target), every plant of the bank finishes within S + 5 °C (σ 0.02 °C as in simavr),
// and seed003 from any start 40–100 °C below its target. A hot start's first pulse is short (40 %
// of the room left at an assumed 20 °C/s: ~1.1 s from 150 °C), and behind seed003's lags (28 and
// 14 s) it peaked at a quarter to a half of the heating rate; the approach re-learnt the rate at
// full power but not the heat its lags held in flight, and overshot to S + 7..15 °C (the same on
// noise realisations 1–4). A rate over 1.5 × the pulse's now puts the approach under the trend
// guard (docs/autotune.md, "A warm start behind a sensor lag").
TEST(Autotune, FromAStandbyTemperatureEveryPlantStaysWithinTargetPlus5) {
  // With the hold's static gain (the standby held over 65 s) and without (M303 sooner).
  for (const bool hold : {false, true}) {
    for (const Plant& p : plants()) {
      std::vector<double> below_c = {60};
      if (p.name == "seed003") below_c = {100, 80, 60, 40};
      for (double below : below_c) {
        const TuneRun r = run(p, 5, true, 0.02, false, 1.0, p.target_c - below, false, 1800, 1, false, hold);
        EXPECT_EQ(r.state, AutotuneState::kFinished) << p.name << " from S − " << below << " hold " << hold << " failure " << static_cast<int>(r.failure);
        EXPECT_TRUE(r.result.hot_start) << p.name;
        EXPECT_EQ(r.result.held_gain, hold) << p.name;
        EXPECT_LE(r.max_c, p.target_c + 5.0) << p.name << " from S − " << below << " hold " << hold;
        EXPECT_EQ(r.overruns, 0) << p.name << " from S − " << below << " hold " << hold;
      }
    }
  }
}

// Tuning near the temperature a printer held (control/steady_hold.h): S − 10 or S + 20 °C after a
// steady hold there. The hold's K gives the approach its steady duty and the probe's S, and
// a probe that saw nothing probes again from a new baseline. Without it (at σ 0.02, seed 1):
// two-node-80W from S − 10 went to S + 6.24 °C (its pulse read S 45 % low, ū 0.30 against 0.157),
// heavy-slow and seed000-4 ended "no heating" from S − 10 (a false heater alarm). Still missed:
// seed000-5 ends "no heating" from S − 10 (its ~130 s dead time outlasts the probe's waits), and
// from S + 20 hotend40w and two-node-30W end "The relay oscillation did not hold", safely below
// (other realisations: fopdt-120-25 times out; docs/autotune.md, "A steady hold").
TEST(Autotune, AfterASteadyHoldNearTheTargetEveryPlantStaysWithinTargetPlus5) {
  for (const Plant& p : plants()) {
    for (const double from : {-10.0, 20.0}) {
      const TuneRun r = run(p, 5, true, 0.02, false, 1.0, p.target_c + from, false, 1800, 1);
      std::printf("%-16s from S %+3.0f: %7.1f s, max %+5.2f, state %d failure %d\n", p.name.c_str(), from, r.duration_s,
                  r.max_c - p.target_c, static_cast<int>(r.state), static_cast<int>(r.failure));
      EXPECT_LE(r.max_c, p.target_c + 5.0) << p.name << " from S " << from;
      EXPECT_EQ(r.overruns, 0) << p.name << " from S " << from;  // stage 10 fits its bin
      EXPECT_TRUE(r.result.hot_start || r.state != AutotuneState::kFinished) << p.name;
      if (p.name != "seed000-5") {
        EXPECT_NE(r.failure, AutotuneFailure::kNoHeating) << p.name << " from S " << from;
      }
    }
  }
}
