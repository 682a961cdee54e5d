// Host rig for "after M303 U1" (issue 7's targets): the fixed-point tune engine (control/autotune.h)
// identifies a double-precision bank plant (design/plant_sim.h) with M303's defaults (C5 F1,
// 128 ms), the board's design (control/autotune_design.h, control/state_feedback_autodesign.h)
// turns that into settings as firmware/controller_autotune.cpp applies them, and the real
// ControllerBank then heats the plant from ambient and meets a part-fan step, as HIL7 does in
// simavr (without its ADC quantisation). Figures as sim/metrics.h defines them.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "control/autotune.h"
#include "control/autotune_design.h"
#include "control/state_feedback_autodesign.h"
#include "design/lti_model.h"
#include "design/plant_sim.h"
#include "design/seed_models.h"
#include "firmware/controller_autotune.h"
#include "firmware/controller_bank.h"
#include "host_tests/controller_rig.h"
#include "host_tests/heat_fan_step.h"
#include "host_tests/hot_start_rig.h"

namespace after_u1 {

constexpr double kPeriodS = firmware::kControlPeriodMs / 1000.0;

struct Plant {
  std::string name;
  design::LtiModel model;
  double target_c, fan_s, run_s;
  double bound_s;  // hotend-sim's physical bound into ±1 °C (docs/bench/README.md, "M303")
};

inline design::LtiModel two_node_with(double block, double heater, double loss, double fan_loss, double rate,
                                      double delay = 0) {
  design::TwoNodeParams p;
  p.block_j_per_k = block;
  p.heater_w = heater;
  p.loss_w_per_k = loss;
  p.loss_fan_w_per_k = fan_loss;
  p.sensor_rate_per_s = rate;
  design::LtiModel m = design::two_node(p);
  m.delay_s = delay;
  return m;
}

// sim/plants.cpp's bank (names as hotend-sim's), with HIL7's fan step and run length.
inline std::vector<Plant> plants() {
  using design::fopdt;
  using design::with_seed_fan;
  const design::TwoNodeParams d;
  return {
      {"hotend40w", design::two_node(), 210, 400, 700, 99.2},
      {"hotend30w", two_node_with(d.block_j_per_k, 30, d.loss_w_per_k, d.loss_fan_w_per_k, d.sensor_rate_per_s), 210,
       400, 700, 138.3},
      {"hotend80w", two_node_with(d.block_j_per_k, 80, d.loss_w_per_k, d.loss_fan_w_per_k, d.sensor_rate_per_s), 210,
       400, 700, 52.6},
      {"light-fast", two_node_with(6, 40, d.loss_w_per_k, d.loss_fan_w_per_k, 1.0), 210, 400, 700, 34.4},
      {"heavy-slow", two_node_with(40, 60, 0.14, 0.14 * 0.097 / 0.068, 1.0 / 25), 210, 600, 900, 219.9},
      {"hotend40w-delay5", two_node_with(d.block_j_per_k, d.heater_w, d.loss_w_per_k, d.loss_fan_w_per_k,
                                         d.sensor_rate_per_s, 5.0),
       210, 400, 700, 104.2},
      {"fopdt-fast", with_seed_fan(fopdt(450, 30, 1)), 210, 400, 700, 16.8},
      {"fopdt-slow", with_seed_fan(fopdt(450, 300, 10)), 210, 400, 700, 167.7},
      {"fopdt-delay25", with_seed_fan(fopdt(450, 120, 25)), 210, 400, 700, 88.1},
      {"seed002", design::seed002(), 210, 400, 700, 33.3},
      {"seed004", design::seed004(), 210, 400, 700, 32.9},
      {"seed003", design::seed003(), 210, 400, 700, 59.3},
  };
}

// seed000-4 / seed000-5 (slow, non-minimum-phase; their tunes are "unsure"), heated to 150 °C as
// hotend-sim's bank does, with HIL7's fan step at 1,800 s and 2,400 s run (sim/CMakeLists.txt).
inline std::vector<Plant> seed000_plants() {
  return {{"seed000-4", design::seed000_4(), 150, 1800, 2400, 730.7},
          {"seed000-5", design::seed000_5(), 150, 1800, 2400, 664.0}};
}

inline const Plant* find(const std::vector<Plant>& ps, const std::string& name) {
  for (const Plant& p : ps)
    if (p.name == name) return &p;
  return nullptr;
}

// How a hot start reached its start temperature (tune()'s start_c).
enum class HotStart : uint8_t {
  kHeld,       // held there long enough for the firmware's steady hold to pass its K (rig: exact)
  kUnheld,     // held there, M303 sent before the hold's 65 s (no K)
  kAfterM109,  // `M109 S<start_c>` from cold on the default PID, M303 at M109's ±1 °C window
};

// M303 E0 S<target> C5 U1 F1 on the plant, from ambient or (start_c > 0) a hot start at start_c
// reached as `how` says; false if it did not finish.
inline bool tune(const Plant& p, unsigned long long noise_seed, double noise_c, control::AutotuneResult* out,
                 double start_c = 0, HotStart how = HotStart::kHeld) {
  design::PlantSim sim(p.model);
  sim.set_noise(noise_c);
  sim.set_noise_seed(noise_seed);
  int32_t hold_gain_q8 = 0;
  if (start_c > 0 && how == HotStart::kAfterM109) {
    host_rig::heat_as_m109(sim, start_c);
  } else if (start_c > 0) {
    const double duty = host_rig::hold_at(sim, p.model, start_c);
    if (how == HotStart::kHeld) hold_gain_q8 = host_rig::held_gain_q8(start_c, duty);
  }
  control::Autotune at;
  at.configure(firmware::kControlPeriodMs, 1800);
  if (!at.start(static_cast<int32_t>(std::lround(p.target_c * 256)), 5, true, control::Autotune::kMeasureAmbient,
                hold_gain_q8))
    return false;
  for (int i = 0; i < 200000; ++i) {
    const control::AutotuneOutput o = at.step(static_cast<int32_t>(std::lround(sim.measured_c() * 256)));
    if (o.state != control::AutotuneState::kRunning) {
      *out = at.result();
      if (std::getenv("AUTOTUNE_SWEEP_LHAT"))
        std::printf("   %s L^ %.2f s D %.2f ratio %.2f late %d\n", p.name.c_str(), at.horizon_ticks() * kPeriodS,
                    out->model.dead_time_q8 / 256.0, at.horizon_ticks() * kPeriodS * 256.0 / out->model.dead_time_q8, out->late_peak);
      return o.state == control::AutotuneState::kFinished;
    }
    sim.set_fan(o.fan_duty / 255.0);
    sim.run(o.duty_q16 / 65535.0, kPeriodS);
  }
  return false;
}

// What U1 applies (firmware/controller_autotune.cpp, AutotuneJob::write_result).
struct Applied {
  firmware::Settings settings;
  control::StateFeedbackConstants sf;
  bool sf_ok = false;
};

inline Applied applied(const control::AutotuneResult& r, control::TunedDesign d, bool use_sf) {
  Applied a;
  a.sf_ok = control::design_tuned_state_feedback(&d, firmware::kControlPeriodMs, &a.sf);
  a.settings = firmware::default_settings();
  a.settings.model = d.model;
  a.settings.model_tuned = firmware::tuned_model_source(r);
  a.settings.pid = d.pid;
  a.settings.controller =
      static_cast<uint8_t>(use_sf && a.sf_ok ? firmware::ControllerId::kStateFeedback : firmware::ControllerId::kPid);
  a.settings.feedforward = 1;
  return a;
}

struct Figures {
  bool ok = false;  // settings accepted, back within ±1 °C at the end
  double overshoot_c = 0, settling_s = 0, settling_ratio = 0, steady_pp_c = 0, steady_mean_c = 0, dip_c = 0;
};

// Heat-up from ambient to the target, hold, part fan 0 → 100 % at fan_s (HIL7's scenario);
// trace: heat_fan_step::run's.
inline Figures run(const Plant& p, const Applied& a, std::vector<double>* trace = nullptr) {
  static firmware::ControllerBank bank{controller_test::load_cell};  // static: as the firmware's
  const firmware::HandOver cold{static_cast<int32_t>(std::lround(p.model.ambient_c * 256)), 0, false};
  bank.init(firmware::default_settings());
  Figures f;
  if (a.sf_ok && !bank.load_state_feedback(a.sf, cold)) return f;
  if (bank.apply(a.settings, cold) != nullptr) return f;
  // Noise ~hotend-sim's ADC noise at 210 °C.
  const heat_fan_step::Result r = heat_fan_step::run(bank, p.model, p.target_c, p.fan_s, p.run_s, 0.05, trace);
  f.ok = std::fabs(r.end_error_c) <= 1.0;
  f.overshoot_c = r.overshoot_c;
  f.settling_s = r.settling_s;
  f.settling_ratio = r.settling_s / p.bound_s;
  f.steady_pp_c = r.steady_pp_c;
  f.steady_mean_c = r.steady_mean_c;
  f.dip_c = r.dip_c;
  return f;
}

// Tune, design and apply as the firmware does, then run: the figures after U1.
inline Figures after_u1(const Plant& p, unsigned long long seed, double noise_c = 0.1,
                        control::AutotuneResult* result = nullptr, bool* chose_sf = nullptr, double start_c = 0,
                        HotStart how = HotStart::kHeld) {
  control::AutotuneResult r{};
  Figures f;
  if (!tune(p, seed, noise_c, &r, start_c, how)) return f;
  if (result) *result = r;
  control::TunedDesign d;
  if (!control::design_from_tune(r, firmware::kControlPeriodMs, &d)) return f;
  control::StateFeedbackConstants sf;
  const bool sf_ok = control::design_tuned_state_feedback(&d, firmware::kControlPeriodMs, &sf);
  const bool use_sf = sf_ok && !control::dead_time_leads(r, d);  // as AutotuneJob::write_result
  if (chose_sf) *chose_sf = use_sf;
  return run(p, applied(r, d, use_sf));
}

}  // namespace after_u1
