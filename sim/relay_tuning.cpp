#include "sim/relay_tuning.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace sim {
namespace {

constexpr double kStepS = 0.01;
constexpr double kMaxS = 40000.0;  // the seed000 models cycle in tens of minutes
constexpr int kCycles = 8;         // measure on the last cycles, after the start-up transient
constexpr int kMeasuredCycles = 3;
// Marlin's M303 keeps each relay phase at least 5 s (temperature.cpp, PID_autotune: the switch
// waits for ELAPSED(ms, t + 5000)); on lag-only plants this, not the plant, sets the period.
constexpr double kMinPhaseS = 5.0;

}  // namespace

RelayResult relay_experiment(const PlantSpec& plant, double target_c, double decision_period_s) {
  RelayResult r;
  const double bias = std::clamp((target_c - plant.ambient_c) / design::dc_gain(plant.model), 0.0, 1.0);
  r.relay_amplitude_duty = std::min(bias, 1.0 - bias);
  if (r.relay_amplitude_duty <= 0.0) return r;

  Plant p(plant, kStepS);
  // Full power first (as M303 does) so the relay starts near the target, not from ambient.
  while (p.temperature_c() < target_c && p.time_s() < kMaxS) p.step(PlantInput{1.0, 0.0});
  const long steps_per_decision = std::max(1L, std::lround(decision_period_s / kStepS));
  bool heating = true;
  double last_switch_s = -kMinPhaseS;
  std::vector<double> heat_starts_s;  // each cycle begins when heating resumes
  std::vector<double> amplitudes_k;   // half the peak-to-peak of the cycle before it
  double lo = target_c, hi = target_c;
  for (long step = 0; static_cast<int>(heat_starts_s.size()) <= kCycles && p.time_s() < kMaxS; ++step) {
    const double y = p.temperature_c();
    lo = std::min(lo, y);
    hi = std::max(hi, y);
    const bool may_switch = step % steps_per_decision == 0 && p.time_s() >= last_switch_s + kMinPhaseS;
    if (may_switch && heating && y > target_c) {
      heating = false;
      last_switch_s = p.time_s();
    } else if (may_switch && !heating && y < target_c) {
      heating = true;
      last_switch_s = p.time_s();
      heat_starts_s.push_back(p.time_s());
      amplitudes_k.push_back((hi - lo) / 2.0);
      lo = hi = y;
    }
    p.step(PlantInput{heating ? bias + r.relay_amplitude_duty : bias - r.relay_amplitude_duty, 0.0});
  }
  if (static_cast<int>(heat_starts_s.size()) <= kCycles) return r;
  const std::size_t n = heat_starts_s.size();
  double amplitude = 0.0;
  for (std::size_t i = n - kMeasuredCycles; i < n; ++i) amplitude += amplitudes_k[i];
  r.amplitude_k = amplitude / kMeasuredCycles;
  r.ultimate_period_s = (heat_starts_s[n - 1] - heat_starts_s[n - 1 - kMeasuredCycles]) / kMeasuredCycles;
  r.ultimate_gain_duty_per_k = 4.0 * r.relay_amplitude_duty / (M_PI * r.amplitude_k);
  r.oscillated = r.amplitude_k > 0.0;
  return r;
}

}  // namespace sim
