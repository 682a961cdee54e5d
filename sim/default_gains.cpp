#include "sim/default_gains.h"

#include <algorithm>
#include <cstdio>
#include <vector>

namespace sim {
namespace {

constexpr double kFitStepS = 0.01;
constexpr double kFitHorizonS = 20000.0;
constexpr double kMarlinOutputScale = 255.0;  // Marlin gains act on a 0–255 output
constexpr double kClosedLoopLagPerDelay = 2.0;  // SIMC tuning parameter tc / τ

// First time the response reaches `level` (linear interpolation between samples).
double crossing_s(const std::vector<double>& s, double level) {
  for (std::size_t k = 0; k < s.size(); ++k)
    if (s[k] >= level) {
      const double prev = k ? s[k - 1] : 0.0;
      const double frac = (level - prev) / (s[k] - prev);
      return (double(k) + frac) * kFitStepS;  // sample k is at (k + 1)·dt
    }
  return double(s.size()) * kFitStepS;
}

}  // namespace

FopdtApproximation fopdt_approximation(const PlantSpec& plant) {
  // Two-point method (28.3 % and 63.2 % of the final value; Smith 1972 / seed 003's graph
  // method): T = 1.5·(t63 − t28), τ = t63 − T.
  FopdtApproximation m;
  m.gain_k = plant.model.dc_gain_k();
  const std::vector<double> s = full_power_step_response_k(plant, kFitStepS, std::size_t(kFitHorizonS / kFitStepS));
  const double t28 = crossing_s(s, 0.283 * m.gain_k);
  const double t63 = crossing_s(s, 0.632 * m.gain_k);
  m.lag_s = 1.5 * (t63 - t28);
  m.delay_s = std::max(0.0, t63 - m.lag_s);
  return m;
}

GainChoice default_gains(const PlantSpec& plant) {
  GainChoice choice;
  choice.model = fopdt_approximation(plant);
  const double k = choice.model.gain_k, t = choice.model.lag_s, tau = choice.model.delay_s;
  // SIMC PI (Skogestad 2003) with the smooth setting tc = 2τ: no derivative (robust to ADC
  // noise) and, on every plant of the bank, no more than ~0.5 °C overshoot for the heat-up step
  // from ambient despite heater saturation; tc = τ ("tight") overshoots 8–13 °C on the
  // delay-dominated seeds. Kc = T/(K·(tc + τ)), Ti = min(T, 4·(tc + τ)).
  const double tc = kClosedLoopLagPerDelay * tau;
  const double kc = t / (k * (tc + tau));
  const double ti = std::min(t, 4.0 * (tc + tau));
  choice.gains = MarlinGains{kMarlinOutputScale * kc, kMarlinOutputScale * kc / ti, 0.0};
  char text[160];
  std::snprintf(text, sizeof text, "SIMC PI, tc = 2τ, on FOPDT K %.1f K, T %.1f s, τ %.1f s", k, t, tau);
  choice.description = text;
  return choice;
}

}  // namespace sim
