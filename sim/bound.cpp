#include "sim/bound.h"

#include <cmath>
#include <cstddef>
#include <vector>

namespace sim {
namespace {

// Fine enough for settling times of tens of seconds, and divides every dead time in the bank.
constexpr double kBoundStepS = 0.05;
constexpr double kMaxHorizonS = 40000.0;
constexpr std::size_t kCoarseCandidates = 100;

// By linearity, the response to "1 until step j, then u_ss" is s[k] − (1 − u_ss)·s[k − j],
// with s the full-power step response. Returns the index after the last sample outside the band
// (0 if never outside), scanning back from the horizon where the band is known to hold.
std::size_t settle_index(const std::vector<double>& s, std::size_t j, double u_ss, double target_k,
                         double band_k) {
  for (std::size_t k = s.size(); k-- > 0;) {
    const double y = s[k] - (k >= j ? (1.0 - u_ss) * s[k - j] : 0.0);
    if (std::fabs(y - target_k) > band_k) return k + 1;
  }
  return 0;
}

// Full-power step response until it has stayed within `tolerance_k` of its final value for
// kQuietS: from there on, the error of any switched response, s[k] − G − (1 − u)(s[k−j] − G),
// is below 2·tolerance, far inside the band.
std::vector<double> settled_step_response(const PlantSpec& spec, double gain_k, double tolerance_k) {
  constexpr double kQuietS = 120.0;
  const std::size_t quiet_steps = static_cast<std::size_t>(kQuietS / kBoundStepS);
  const std::size_t max_steps = static_cast<std::size_t>(kMaxHorizonS / kBoundStepS);
  Plant plant(spec, kBoundStepS);
  std::vector<double> s;
  std::size_t quiet = 0;
  while (quiet < quiet_steps && s.size() < max_steps) {
    plant.step(PlantInput{1.0, 0.0});
    s.push_back(plant.temperature_c() - spec.ambient_c);
    quiet = std::fabs(s.back() - gain_k) < tolerance_k ? quiet + 1 : 0;
  }
  return s;
}

}  // namespace

PhysicalBound physical_bound(const PlantSpec& plant, double target_c, double band_c) {
  PhysicalBound bound;
  const double gain_k = design::dc_gain(plant.model, 0.0);
  const double target_k = target_c - plant.ambient_c;
  bound.steady_duty = target_k / gain_k;
  if (!(bound.steady_duty > 0.0 && bound.steady_duty <= 1.0)) return bound;
  bound.reachable = true;

  std::vector<double> s = settled_step_response(plant, gain_k, band_c / 20.0);
  // The switch is never later than the moment full power leaves the band upwards.
  std::size_t last_switch = 0;
  while (last_switch < s.size() && s[last_switch] < target_k + band_c) ++last_switch;
  s.resize(s.size() + last_switch, gain_k);  // a switched response needs s up to k − j
  // (extended with its final value: within tolerance, see settled_step_response)

  auto best_in = [&](std::size_t from, std::size_t to, std::size_t stride, std::size_t& best_j) {
    std::size_t best = s.size() + 1;
    for (std::size_t j = from; j <= to; j += stride) {
      const std::size_t k = settle_index(s, j, bound.steady_duty, target_k, band_c);
      if (k < best) best = k, best_j = j;
    }
    return best;
  };
  const std::size_t stride = std::max<std::size_t>(1, last_switch / kCoarseCandidates);
  std::size_t best_j = 0;
  best_in(0, last_switch, stride, best_j);
  const std::size_t from = best_j > stride ? best_j - stride : 0;
  const std::size_t best_k = best_in(from, std::min(last_switch, best_j + stride), 1, best_j);
  bound.settling_s = double(best_k) * kBoundStepS;
  bound.switch_s = double(best_j) * kBoundStepS;
  return bound;
}

}  // namespace sim
