// Direct double-precision Mamdani evaluation of the fuzzy supervisor, exactly as seed 002
// describes it: triangular input sets, max–min inference, centroid defuzzification. HOST ONLY
// (design and tests): the firmware uses the fixed-point surfaces of fuzzy_surface.h instead and
// must never include this header (avr-gcc would link soft-float routines).
//
// This is deliberately the plain textbook algorithm — all 49 rules fired, the aggregated output
// sampled on a fine grid and integrated numerically — so that it is an independent check on the
// compile-time generator, which integrates the same function exactly piece by piece.
#pragma once

#include <algorithm>
#include <cmath>

#include "control/fuzzy_rules.h"

namespace fuzzy {
namespace reference {

constexpr double kInputMax = 3.0;   // input universe −3…3 (seed 002)
constexpr double kOutputMax = 3.0;  // output universe 0…3 (seed 002)

// Membership of universe value u in input set i (centred on i − 3, half-width 1). The end sets
// are shoulders: NB stays 1 below −3, PB stays 1 above 3.
inline double input_membership(int i, double u) {
  const double centre = i - 3.0;
  if (i == 0 && u <= centre) return 1.0;
  if (i == kSets - 1 && u >= centre) return 1.0;
  return std::max(0.0, 1.0 - std::fabs(u - centre));
}

// Membership of output value y (0…3) in output set k (centred on k/2, half-width 1/2).
// Integration runs over the universe 0…3 only, so the end sets count as half triangles
// (MATLAB's Fuzzy toolbox, which seed 002 used, behaves the same way).
inline double output_membership(int k, double y) {
  const double centre = 0.5 * k;
  return std::max(0.0, 1.0 - std::fabs(y - centre) / 0.5);
}

// The defuzzified output for universe inputs (e_u, ec_u), each clamped to −3…3 as the quantizer
// would. Max–min: rule strength = min(μe, μec); output set k clipped at the max strength of
// the rules concluding k; aggregated by max; centroid by the trapezoid rule on `samples`
// intervals (error ~1e-6 with the default, far below the fixed-point tables' resolution).
inline double mamdani(const RuleTable& rules, double e_u, double ec_u, int samples = 6000) {
  e_u = std::min(kInputMax, std::max(-kInputMax, e_u));
  ec_u = std::min(kInputMax, std::max(-kInputMax, ec_u));
  double clip[kSets] = {};
  for (int i = 0; i < kSets; ++i) {
    for (int j = 0; j < kSets; ++j) {
      const double strength = std::min(input_membership(i, e_u), input_membership(j, ec_u));
      double& c = clip[rules.out[i][j]];
      c = std::max(c, strength);
    }
  }
  double area = 0, moment = 0;
  const double dy = kOutputMax / samples;
  for (int n = 0; n <= samples; ++n) {
    const double y = n * dy;
    double mu = 0;
    for (int k = 0; k < kSets; ++k) mu = std::max(mu, std::min(clip[k], output_membership(k, y)));
    const double weight = (n == 0 || n == samples) ? 0.5 : 1.0;  // trapezoid end points
    area += weight * mu;
    moment += weight * mu * y;
  }
  return moment / area;  // area > 0: the input sets cover the universe, some rule fires ≥ 0.5
}

// Seed 002's quantization: universe value = factor × physical value, clamped to the universe.
// Factor 0.4 for e in °C (|e| ≥ 7.5 °C saturates), 0.6 for ec in °C/s (|ec| ≥ 5 °C/s saturates).
inline double quantize(double factor, double value) {
  return std::min(kInputMax, std::max(-kInputMax, factor * value));
}

}  // namespace reference
}  // namespace fuzzy
