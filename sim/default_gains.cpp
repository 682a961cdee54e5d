#include "sim/default_gains.h"

#include <cstdio>
#include <vector>

namespace sim {
namespace {

constexpr double kFitStepS = 0.05;
constexpr double kFitHorizonS = 20000.0;  // long enough for every plant to settle (seed000: ~1 h)
constexpr double kClosedLoopLagPerDelay = 2.0;  // SIMC's tuning parameter τc / τ

}  // namespace

tuning::Fopdt fopdt_approximation(const PlantSpec& plant) {
  const std::vector<double> rise =
      full_power_step_response_k(plant, kFitStepS, static_cast<std::size_t>(kFitHorizonS / kFitStepS));
  std::vector<double> time_s{0.0}, temp_c{plant.ambient_c};  // the step at t = 0, from ambient
  for (std::size_t k = 0; k < rise.size(); ++k) {
    time_s.push_back(double(k + 1) * kFitStepS);
    temp_c.push_back(plant.ambient_c + rise[k]);
  }
  return tuning::fit_fopdt_two_point(time_s, temp_c, 0.0, 1.0);
}

GainChoice default_gains(const PlantSpec& plant) {
  GainChoice choice;
  choice.model = fopdt_approximation(plant);
  // SIMC PI with the smooth setting τc = 2τ: no derivative (robust to ADC noise) and, in a
  // double-precision model of the firmware's PID on every plant of the bank, at most ~0.6 °C
  // overshoot on the heat-up from ambient despite heater saturation. τc = τ ("tight") overshoots
  // 8–13 °C on the delay-dominated seeds, AMIGO 15–35 °C.
  const tuning::MarlinGains g = tuning::simc(choice.model, kClosedLoopLagPerDelay * choice.model.tau_s);
  choice.gains = MarlinGains{g.kp, g.ki, g.kd};
  char text[160];
  std::snprintf(text, sizeof text, "SIMC PI, τc = 2τ, on FOPDT K %.1f K, T %.1f s, τ %.1f s",
                choice.model.k_c_per_duty, choice.model.t_s, choice.model.tau_s);
  choice.description = text;
  return choice;
}

}  // namespace sim
