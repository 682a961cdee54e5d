// Compile-time generator of the fuzzy surfaces (fuzzy_surface.h) from the rule tables
// (fuzzy_rules.h): at every grid node, Mamdani max–min inference and centroid defuzzification
// evaluated by the compiler — the grid is never pasted. Floating point appears only in constant
// expressions, so the firmware image stays float-free (like thermistor.h's tables).
//
// Templated on the floating type because avr-gcc 5.4's double is 32 bits: the host tests
// rebuild the grid with float to check what the AVR compiler produces.
//
// Integration here is exact, not sampled: with evenly spaced output triangles overlapping by
// half, between two neighbouring set centres only those two sets are non-zero, and the
// aggregated membership max(min(wa, 1−t), min(wb, t)) is piecewise linear with its corners among
// t ∈ {1−wa, wb, ½, wa, 1−wb}. Simpson's rule on each linear piece integrates μ and y·μ exactly.
// (The host reference, fuzzy_reference.h, samples instead: two independent routes.)
#pragma once

#include <stdint.h>

#include "control/fuzzy_rules.h"
#include "control/fuzzy_surface.h"

namespace fuzzy {

template <int kStepShift> struct Surfaces {
  Cell cell[Grid<kStepShift>::kCells];
};

// The surfaces can be folded (fuzzy_surface.h) only if every table is point-symmetric.
constexpr bool point_symmetric(const RuleTable& t) {
  for (int i = 0; i < kSets; ++i)
    for (int j = 0; j < kSets; ++j)
      if (t.out[i][j] != t.out[kSets - 1 - i][kSets - 1 - j]) return false;
  return true;
}
static_assert(point_symmetric(kRulesKp) && point_symmetric(kRulesKi) && point_symmetric(kRulesKd),
              "the folded surface storage needs point-symmetric rule tables");

namespace gen {

template <class Real> constexpr Real min(Real a, Real b) { return a < b ? a : b; }
template <class Real> constexpr Real max(Real a, Real b) { return a < b ? b : a; }

// Input set i: triangle centred on i − 3, half-width 1; NB and PB are shoulders.
template <class Real> constexpr Real input_membership(int i, Real u) {
  const Real d = u - Real(i - 3);
  if ((i == 0 && d <= 0) || (i == kSets - 1 && d >= 0)) return 1;
  const Real a = d < 0 ? -d : d;
  return a < 1 ? 1 - a : Real(0);
}

template <class Real> struct Clips {
  Real w[kSets];  // clip level of each output set: max strength of the rules concluding it
};

template <class Real> constexpr Clips<Real> fire(const RuleTable& rules, Real e_u, Real ec_u) {
  Clips<Real> c{{0, 0, 0, 0, 0, 0, 0}};  // spelled out: `c{}` crashes avr-gcc 5.4's constexpr
  for (int i = 0; i < kSets; ++i) {
    const Real me = input_membership(i, e_u);
    if (me <= 0) continue;
    for (int j = 0; j < kSets; ++j) {
      const Real strength = min(me, input_membership(j, ec_u));
      const int k = rules.out[i][j];  // (no Real& here: avr-gcc 5.4's constexpr rejects it)
      c.w[k] = max(c.w[k], strength);
    }
  }
  return c;
}

// Aggregated membership between centres k and k+1 at local t ∈ [0, 1].
template <class Real> constexpr Real envelope(Real wa, Real wb, Real t) {
  return max(min(wa, 1 - t), min(wb, t));
}

// Centroid on the output universe 0…3 (centres at k/2), integrated exactly piece by piece.
template <class Real> constexpr Real centroid(const Clips<Real>& c) {
  Real area = 0, moment = 0;  // in half-step units of y (y = (k + t) / 2)
  for (int k = 0; k + 1 < kSets; ++k) {
    const Real wa = c.w[k], wb = c.w[k + 1];
    if (wa <= 0 && wb <= 0) continue;
    Real t[7] = {0, 1, 1 - wa, wb, Real(0.5), wa, 1 - wb};
    for (int a = 1; a < 7; ++a)  // insertion sort of the corner candidates
      for (int b = a; b > 0 && t[b] < t[b - 1]; --b) {
        const Real s = t[b];
        t[b] = t[b - 1];
        t[b - 1] = s;
      }
    for (int s = 0; s + 1 < 7; ++s) {
      const Real t0 = t[s], t1 = t[s + 1];
      if (!(t1 > t0)) continue;
      const Real tm = (t0 + t1) / 2;
      const Real m0 = envelope(wa, wb, t0), mm = envelope(wa, wb, tm), m1 = envelope(wa, wb, t1);
      const Real h6 = (t1 - t0) / 6;
      area += h6 * (m0 + 4 * mm + m1);
      moment += h6 * ((k + t0) * m0 + 4 * (k + tm) * mm + (k + t1) * m1);
    }
  }
  return moment / area / 2;  // area > 0: the input sets cover the universe
}

template <class Real> constexpr Real defuzzify(const RuleTable& rules, Real e_u, Real ec_u) {
  return centroid(fire(rules, e_u, ec_u));
}

template <class Real> constexpr uint8_t to_q6(Real v) { return static_cast<uint8_t>(v * 64 + Real(0.5)); }

// Stops constant evaluation (the compiler names this function) when a table is not symmetric;
// avr-gcc 5.4 rejects the cleaner call to a non-constexpr function.
constexpr int require_point_symmetric(bool ok) { return 1 / (ok ? 1 : 0) - 1; }

}  // namespace gen

// The folded grid: rows e = 0…3, columns ec = −3…3, node spacing 2^kStepShift / 256.
template <int kStepShift, class Real = double>
constexpr Surfaces<kStepShift> make_surfaces(const RuleTable& kp, const RuleTable& ki, const RuleTable& kd) {
  using G = Grid<kStepShift>;
  gen::require_point_symmetric(point_symmetric(kp) && point_symmetric(ki) && point_symmetric(kd));
  Surfaces<kStepShift> s{};
  for (int r = 0; r < G::kRows; ++r) {
    const Real e_u = Real(r * G::kStepQ8) / 256;
    for (int c = 0; c < G::kCols; ++c) {
      const Real ec_u = Real(c * G::kStepQ8 - kUniverseMaxQ8) / 256;
      s.cell[r * G::kCols + c] = Cell{gen::to_q6(gen::defuzzify(kp, e_u, ec_u)),
                                      gen::to_q6(gen::defuzzify(ki, e_u, ec_u)),
                                      gen::to_q6(gen::defuzzify(kd, e_u, ec_u))};
    }
  }
  return s;
}

// The grid the firmware stores, from the default rule base.
template <class Real = double> constexpr Surfaces<kSurfaceStepShift> make_default_surfaces() {
  return make_surfaces<kSurfaceStepShift, Real>(kRulesKp, kRulesKi, kRulesKd);
}

}  // namespace fuzzy
