// The M303 identification engine (control/autotune.h) on simulated hotends (control/lti_simulate.h):
// finishes, never above target + 5 °C, within the duration targets, and identifies K, T, L, F.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "control/autotune.h"
#include "control/lti_model.h"
#include "control/lti_seed_models.h"
#include "control/lti_simulate.h"

namespace {

using control::Autotune;
using control::AutotuneFailure;
using control::AutotuneState;
namespace design = control::design;

constexpr double kPeriodS = 0.128;

struct Plant {
  std::string name;
  design::LtiModel model;
  int fan_state;        // PlantSim: the state the fan cools (-1 = output)
  double target_c;
  double start_c;       // 25 = cold; else held there by a steady duty before the tune
  bool fopdt;           // K, T, L, F accuracy asserted
  double k, t, l, lag;  // true values (lag: the second lag, 0 if none)
  double budget_s;      // duration target (0: full-power heat-up + 180 s)
};

double fan_pct(const design::LtiModel& m, double k) { return m.fan_loss_per_k * k * 100.0; }

Plant fopdt_plant(const std::string& name, double k, double t, double l, double target = 210) {
  design::LtiModel m = design::with_seed_fan(design::fopdt(k, t, l));
  return Plant{name, m, -1, target, 25, true, k, t, l, 0, 0};
}

Plant two_node_plant(const std::string& name, design::TwoNodeParams p, double target = 210, double delay = 0) {
  design::LtiModel m = design::two_node(p);
  m.delay_s = delay;
  const double k = p.heater_w / p.loss_w_per_k;
  return Plant{name, m, 0, target, 25, false, k, p.block_j_per_k / p.loss_w_per_k, delay, 1.0 / p.sensor_rate_per_s, 0};
}

std::vector<Plant> plants() {
  std::vector<Plant> v;
  Plant h = two_node_plant("hotend40w", design::TwoNodeParams());
  h.budget_s = 240;
  v.push_back(h);
  v.push_back(fopdt_plant("seed002", 450, 24, 20.7));
  v.push_back(fopdt_plant("seed004", 450, 25.5, 19.5));
  Plant s3{"seed003", design::seed003(), -1, 210, 25, false, 450, 0.64 * 44.2696, 0, 0.32 * 44.2696, 0};
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
  Plant s4{"seed000-4", design::seed000_4(), -1, 150, 25, false, 450, 0, 0, 0, 2 * 730.7};
  Plant s5{"seed000-5", design::seed000_5(), -1, 150, 25, false, 450, 0, 0, 0, 2 * 664.0};
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
};

// Time for 100 % duty to bring the plant from its start to the target.
double full_power_heatup_s(const Plant& p, double start_duty) {
  design::PlantSim sim(p.model, p.fan_state);
  for (int i = 0; i < 40000 && start_duty > 0; ++i) sim.run(start_duty, kPeriodS);
  const double t0 = sim.time_s();
  while (sim.true_c() < p.target_c && sim.time_s() - t0 < 5000) sim.run(1.0, kPeriodS);
  return sim.time_s() - t0;
}

TuneRun run(const Plant& p, uint8_t cycles = 3, bool fan = true, double noise = 0.1, bool trace = false,
        double heater_scale = 1.0, double start_c = -1) {
  TuneRun r;
  if (start_c < 0) start_c = p.start_c;
  design::PlantSim sim(p.model, p.fan_state);
  sim.set_noise(noise);
  sim.set_gain_error(heater_scale);
  double start_duty = 0;
  if (start_c > 25.5) {
    // Hold the start temperature a long while (as a printer idling there) before the tune.
    start_duty = (start_c - 25.0) / design::dc_gain(p.model);
    for (int i = 0; i < 40000; ++i) sim.run(start_duty, kPeriodS);
  }
  r.heatup_s = full_power_heatup_s(p, start_duty);
  Autotune at;
  at.configure(128, 3600);
  at.start(static_cast<int32_t>(std::lround(p.target_c * 256)), cycles, fan);
  const double t0 = sim.time_s();
  for (int i = 0; i < 60000; ++i) {
    const double m = sim.measured_c();
    const control::AutotuneOutput out = at.step(static_cast<int32_t>(std::lround(m * 256)));
    if (at.phase() == Autotune::Phase::kApproach && r.approach_s == 0) r.approach_s = sim.time_s() - t0;
    if (at.phase() == Autotune::Phase::kRelay && r.relay_s == 0) r.relay_s = sim.time_s() - t0;
    if (out.fan_duty > 0 && r.fan_s == 0) r.fan_s = sim.time_s() - t0;
    if (out.event == control::AutotuneEvent::kCycle || out.event == control::AutotuneEvent::kUltimate) ++r.cycles;
    if (trace && (i % 8 == 0 || out.event != control::AutotuneEvent::kNone)) {
      std::printf("%7.1f ph%d y %7.2f duty %5.3f fan %3d S %d L %d invT %d ev %d\n", sim.time_s() - t0,
                  static_cast<int>(at.phase()), sim.true_c(), out.duty_q16 / 65535.0, out.fan_duty, at.slope_q8(),
                  at.horizon_ticks(), at.inv_t_q16(), static_cast<int>(out.event));
    }
    if (out.state != AutotuneState::kRunning) {
      r.state = out.state;
      r.failure = out.failure;
      break;
    }
    sim.set_fan(out.fan_duty / 255.0);
    sim.run(out.duty_q16 / 65535.0, kPeriodS);
    if (sim.true_c() > r.max_c) r.max_c = sim.true_c();
  }
  r.duration_s = sim.time_s() - t0;
  r.result = at.result();
  return r;
}

double q8(int32_t v) { return v / 256.0; }

TEST(Autotune, Trace) {
  const char* which = std::getenv("AUTOTUNE_TRACE");
  if (!which) GTEST_SKIP() << "set AUTOTUNE_TRACE=<plant> to print a trace";
  for (const Plant& p : plants()) {
    if (p.name != which) continue;
    TuneRun r = run(p, 3, true, 0.1, true);
    std::printf("state %d failure %d duration %.1f max %.2f K %.1f T %.1f L %.2f F %.1f\n", static_cast<int>(r.state),
                static_cast<int>(r.failure), r.duration_s, r.max_c - p.target_c, q8(r.result.model.rise_q8),
                q8(r.result.model.time_constant_q8), q8(r.result.model.dead_time_q8), q8(r.result.model.fan_loss_pct_q8));
  }
}

TEST(Autotune, Table) {
  std::printf("%-16s %6s %6s %6s %6s | %7s %7s | %6s %6s | %6s %6s | %5s %5s | %5s\n", "plant", "dur s", "budget", "maxS", "cyc",
              "K id", "K true", "T id", "T true", "L id", "L true", "F id", "F tru", "lag");
  for (const Plant& p : plants()) {
    TuneRun r = run(p);
    const double budget = p.budget_s > 0 ? p.budget_s : r.heatup_s + 180;
    std::printf("%-16s %6.1f %6.1f %6.2f %6d | %7.1f %7.1f | %6.1f %6.1f | %6.2f %6.2f | %5.1f %5.1f | %5.2f | %5.0f %5.0f %5.0f %s%s\n", p.name.c_str(),
                r.duration_s, budget, r.max_c - p.target_c, r.cycles, q8(r.result.model.rise_q8), p.k,
                q8(r.result.model.time_constant_q8), p.t, q8(r.result.model.dead_time_q8), p.l,
                q8(r.result.model.fan_loss_pct_q8), fan_pct(p.model, p.k), p.lag, r.approach_s, r.relay_s, r.fan_s,
                r.state == AutotuneState::kFinished ? "" : " FAILED ", r.state == AutotuneState::kFinished ? "" : std::to_string(static_cast<int>(r.failure)).c_str());
  }
}

}  // namespace
