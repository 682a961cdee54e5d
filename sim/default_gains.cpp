#include "sim/default_gains.h"

#include <cstdio>
#include <stdexcept>

#include "sim/relay_tuning.h"

namespace sim {
namespace {

constexpr double kFitStepS = 0.05;
constexpr double kFitHorizonS = 20000.0;
constexpr double kFirmwareControlPeriodS =
    0.128;  // brief: 128 ticks of 1 ms  // long enough for every plant to settle (seed000: ~1 h)

tuning::MarlinGains apply_rule(const std::string& rule, const tuning::Fopdt& m) {
  // SIMC PI with the smooth setting τc = 2τ is the default: no derivative (robust to ADC noise)
  // and, in a double-precision model of the firmware's PID on every plant of the bank, at most
  // ~0.6 °C overshoot on the heat-up from ambient despite heater saturation. τc = τ ("tight")
  // overshoots 8–13 °C on the delay-dominated seeds, AMIGO 15–35 °C.
  if (rule == "simc") return tuning::simc(m, 2.0 * m.tau_s);
  if (rule == "simc-tight") return tuning::simc(m, m.tau_s);
  if (rule == "amigo") return tuning::amigo(m);
  if (rule == "cohen-coon") return tuning::cohen_coon(m);
  if (rule == "zn-step") return tuning::ziegler_nichols_step(m);
  throw std::invalid_argument("unknown gain rule \"" + rule + "\"");
}

// Marlin's M303 "classic PID" from a relay experiment: Kp = 0.6·Ku, Ki = 2·Kp/Pu, Kd = Kp·Pu/8
// (Ziegler & Nichols 1942, ultimate-cycle rule), Ku on Marlin's 0–255 output scale.
GainChoice zn_relay(const PlantSpec& plant, double target_c, const tuning::Fopdt& model) {
  const RelayResult relay = relay_experiment(plant, target_c, kFirmwareControlPeriodS);
  if (!relay.oscillated) throw std::invalid_argument("zn-relay: no relay oscillation on " + plant.name);
  GainChoice choice;
  choice.model = model;
  const double kp = 0.6 * 255.0 * relay.ultimate_gain_duty_per_k;
  choice.gains = MarlinGains{kp, 2.0 * kp / relay.ultimate_period_s, kp * relay.ultimate_period_s / 8.0};
  char text[160];
  std::snprintf(text, sizeof text, "zn-relay: Ku %.3f (0–255 per °C), Pu %.1f s at %.0f °C",
                255.0 * relay.ultimate_gain_duty_per_k, relay.ultimate_period_s, target_c);
  choice.description = text;
  return choice;
}

}  // namespace

const std::vector<std::string>& gain_rule_names() {
  static const std::vector<std::string> names{"simc",       "simc-tight", "amigo",
                                              "cohen-coon", "zn-step",    "zn-relay"};
  return names;
}

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

GainChoice gains_by_rule(const PlantSpec& plant, const std::string& rule, double target_c) {
  GainChoice choice;
  choice.model = fopdt_approximation(plant);
  if (rule == "zn-relay") return zn_relay(plant, target_c, choice.model);
  char text[160];
  const tuning::MarlinGains g = apply_rule(rule, choice.model);
  choice.gains = MarlinGains{g.kp, g.ki, g.kd};
  std::snprintf(text, sizeof text, "%s on FOPDT K %.1f K, T %.1f s, τ %.1f s", rule.c_str(),
                choice.model.k_c_per_duty, choice.model.t_s, choice.model.tau_s);
  choice.description = text;
  return choice;
}

}  // namespace sim
