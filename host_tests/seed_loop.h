// Closed-loop rig for issue 7's "every controller passes on the seed plants": the real
// ControllerBank (as the firmware steps it, 128 ms) and ThermalWatch against a double-precision
// seed plant (design/plant_sim.h), set up as sim/controller_setup.cpp sets each controller up
// (gains by SIMC on the plant's two-point FOPDT fit, the M307 model of that fit), then the HIL3
// scenario: heat to the target, hold, part fan 0 → 100 % (metrics as sim/metrics.h defines them).
#pragma once

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "design/lti_model.h"
#include "design/plant_sim.h"
#include "design/seed_models.h"
#include "design/tuning.h"
#include "firmware/controller_bank.h"
#include "host_tests/controller_rig.h"
#include "host_tests/heat_fan_step.h"

namespace seed_loop {

constexpr double kPeriodS = firmware::kControlPeriodMs / 1000.0;

using controller_test::load_cell;  // the firmware's default rule surfaces

struct SeedPlant {
  const char* name;
  design::LtiModel model;
  double target_c, fan_at_s, run_s, bound_s;  // sim/CMakeLists.txt's HIL3_PLANTS, docs/bench bounds
};

inline std::vector<SeedPlant> seed_plants() {
  return {{"seed002", design::seed002(), 210, 300, 420, 33.3},
          {"seed004", design::seed004(), 210, 300, 420, 32.9},
          {"seed003", design::seed003(), 210, 300, 480, 59.3},
          {"seed000-4", design::seed000_4(), 150, 1800, 3600, 730.7},
          {"seed000-5", design::seed000_5(), 150, 1800, 3600, 664.0}};
}

// sim/default_gains.cpp's fit: the full-power step from ambient, two-point FOPDT.
inline tuning::Fopdt fopdt_fit(const design::LtiModel& m) {
  design::PlantSim p(m);
  std::vector<double> t{0.0}, y{m.ambient_c};
  for (int k = 1; k <= 100000; ++k) {  // 0.2 s samples, 20,000 s as sim/default_gains.cpp (seed000-5's tail)
    p.run(1.0, 0.2);
    t.push_back(0.2 * k);
    y.push_back(p.true_c());
  }
  return tuning::fit_fopdt_two_point(t, y, 0.0, 1.0);
}

// The M307 model sim/plant_model.cpp sends: exact for a FOPDT, else the fit; F from the fan path.
inline control::HotendModel m307_for(const design::LtiModel& m, const tuning::Fopdt& fit) {
  const bool fopdt = m.n == 1 && m.delay_s > 0;
  const double rise = fopdt ? design::dc_gain(m) : fit.k_c_per_duty;
  const double c = fopdt ? -1.0 / m.a(0, 0) : fit.t_s;
  const double d = fopdt ? m.delay_s : fit.tau_s;
  const double f = 100.0 * (design::dc_gain(m, 0.0) / design::dc_gain(m, 1.0) - 1.0);
  auto q8 = [](double x) { return static_cast<int32_t>(std::lround(x * 256)); };
  return control::HotendModel{q8(rise), q8(c), q8(d), q8(f)};
}

struct Figures {
  double overshoot_c = 0, steady_mean_c = 0, steady_pp_c = 0, dip_c = 0, recovery_s = -1;
  firmware::Fault fault = firmware::Fault::kNone;
  double fault_s = -1;
  double recovery_ratio(double bound_s) const { return recovery_s < 0 ? 1e9 : recovery_s / bound_s; }
  // HIL3's limits (sim/CMakeLists.txt).
  bool passes(double bound_s) const {
    return fault == firmware::Fault::kNone && overshoot_c <= 3 && steady_pp_c <= 1 && std::fabs(steady_mean_c) <= 0.5 &&
           recovery_ratio(bound_s) <= 2;
  }
};

// The plant's fit, computed once per plant (20,000 s of step response: ~0.5 s each).
inline tuning::Fopdt cached_fit(const SeedPlant& plant) {
  static std::map<std::string, tuning::Fopdt> fits;
  const auto found = fits.find(plant.name);
  if (found != fits.end()) return found->second;
  return fits[plant.name] = fopdt_fit(plant.model);
}

// controller: "pid", "pid+ff", "fuzzy", "fuzzy+ff".
inline Figures run(const SeedPlant& plant, const std::string& controller) {
  const tuning::Fopdt fit = cached_fit(plant);
  const bool ff = controller.find("+ff") != std::string::npos;
  const bool fuzzy = controller.rfind("fuzzy", 0) == 0;
  firmware::Settings s = firmware::default_settings();
  s.pid = tuning::to_q16(tuning::simc(fit, ff ? fit.tau_s : 2.0 * fit.tau_s));  // "simc-tight" / "simc"
  s.model = m307_for(plant.model, fit);
  s.model_tuned = 1;
  s.controller = static_cast<uint8_t>(fuzzy ? firmware::ControllerId::kFuzzyPid : firmware::ControllerId::kPid);
  s.feedforward = ff ? 1 : 0;
  static firmware::ControllerBank bank{load_cell};  // static: as big as the firmware's (no stack hog)
  bank.init(firmware::default_settings());
  const gcode::FlashText* refused = bank.apply(s, firmware::HandOver{25 * 256, 0, false});
  Figures f;
  if (refused != nullptr) {
    f.fault = firmware::Fault::kHeatingFailed;
    return f;
  }
  const heat_fan_step::Result r = heat_fan_step::run(bank, plant.model, plant.target_c, plant.fan_at_s, plant.run_s, 0.0);
  f.overshoot_c = r.overshoot_c;
  f.steady_mean_c = r.steady_mean_c;
  f.steady_pp_c = r.steady_pp_c;
  f.dip_c = r.dip_c;
  f.recovery_s = r.recovery_s;
  f.fault = r.fault;
  f.fault_s = r.fault_s;
  return f;
}

}  // namespace seed_loop
