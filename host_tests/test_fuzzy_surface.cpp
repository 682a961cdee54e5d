// The fixed-point fuzzy surfaces (compile-time grid + bilinear interpolation) against the
// direct double-precision Mamdani evaluation of the same rule tables.
#include "design/fuzzy_reference.h"
#include "control/fuzzy_surface.h"
#include "control/fuzzy_surface_gen.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace {

using fuzzy::Cell;
using fuzzy::kSurfaceStepShift;
using fuzzy::reference::mamdani;
using Grid = fuzzy::Grid<kSurfaceStepShift>;

constexpr auto kSurfaces = fuzzy::make_default_surfaces();            // what host g++ builds
constexpr auto kSurfacesAvr = fuzzy::make_default_surfaces<float>();  // avr-gcc: double is 32-bit

Cell load_host(uint16_t i) { return kSurfaces.cell[i]; }

const fuzzy::RuleTable* const kTables[3] = {&fuzzy::kRulesKp, &fuzzy::kRulesKi, &fuzzy::kRulesKd};
const char* const kNames[3] = {"dkp", "dki", "dkd"};

uint8_t cell_value(const Cell& c, int t) { return t == 0 ? c.dkp_q6 : (t == 1 ? c.dki_q6 : c.dkd_q6); }
uint16_t delta_value(const fuzzy::Deltas& d, int t) { return t == 0 ? d.dkp_q8 : (t == 1 ? d.dki_q8 : d.dkd_q8); }

TEST(FuzzyReference, RuleNodesGiveTheirOutputSetsCentroid) {
  // At integer inputs exactly one rule fires, fully: the output is its set's centroid — the set
  // centre k/2, except the half triangles at the universe's ends (centroid 1/6 from the end).
  for (int t = 0; t < 3; ++t)
    for (int i = 0; i < fuzzy::kSets; ++i)
      for (int j = 0; j < fuzzy::kSets; ++j) {
        const int k = kTables[t]->out[i][j];
        const double expected = k == 0 ? 1.0 / 6 : (k == 6 ? 3.0 - 1.0 / 6 : 0.5 * k);
        EXPECT_NEAR(mamdani(*kTables[t], i - 3.0, j - 3.0), expected, 1e-5) << kNames[t];
      }
}

TEST(FuzzySurfaceGen, ExactIntegrationAgreesWithSampledReferenceEverywhere) {
  // The generator's piecewise-exact centroid and the reference's sampled one are two routes
  // to the same number, at any input, not only at grid nodes.
  for (int t = 0; t < 3; ++t) {
    double worst = 0;
    for (double e = -3.2; e <= 3.2; e += 0.0731)
      for (double ec = -3.2; ec <= 3.2; ec += 0.0617) {
        const double ex = fuzzy::gen::defuzzify<double>(*kTables[t], std::fmin(3.0, std::fmax(-3.0, e)),
                                                        std::fmin(3.0, std::fmax(-3.0, ec)));
        worst = std::fmax(worst, std::fabs(ex - mamdani(*kTables[t], e, ec, 3000)));
      }
    EXPECT_LT(worst, 2e-5) << kNames[t];
  }
}

TEST(FuzzySurfaceGen, GridNodesAreTheReferenceRoundedToQ6) {
  for (int r = 0; r < Grid::kRows; ++r)
    for (int c = 0; c < Grid::kCols; ++c) {
      const double e = r * Grid::kStepQ8 / 256.0, ec = (c * Grid::kStepQ8 - 768) / 256.0;
      for (int t = 0; t < 3; ++t)
        EXPECT_NEAR(cell_value(kSurfaces.cell[r * Grid::kCols + c], t) / 64.0, mamdani(*kTables[t], e, ec),
                    0.5 / 64 + 1e-4)
            << kNames[t] << " e " << e << " ec " << ec;
    }
}

TEST(FuzzySurfaceGen, AvrSinglePrecisionBuildsTheSameGrid) {
  // avr-gcc evaluates the generator in 32-bit floats; a rounding tie may flip one Q6 step.
  int differing = 0;
  for (int n = 0; n < Grid::kCells; ++n)
    for (int t = 0; t < 3; ++t) {
      const int d = cell_value(kSurfaces.cell[n], t) - cell_value(kSurfacesAvr.cell[n], t);
      EXPECT_LE(std::abs(d), 1);
      differing += d != 0;
    }
  EXPECT_LE(differing, 3);
}

TEST(FuzzySurface, InterpolationReproducesGridNodesExactly) {
  for (int r = 0; r < Grid::kRows; ++r)
    for (int c = 0; c < Grid::kCols; ++c) {
      const int16_t e = static_cast<int16_t>(r * Grid::kStepQ8), ec = static_cast<int16_t>(c * Grid::kStepQ8 - 768);
      const Cell& node = kSurfaces.cell[r * Grid::kCols + c];
      for (int16_t sign : {1, -1}) {  // the folded half too
        const fuzzy::Deltas d = fuzzy::interpolate<kSurfaceStepShift>(load_host, sign * e, sign * ec);
        for (int t = 0; t < 3; ++t) EXPECT_EQ(delta_value(d, t), 4 * cell_value(node, t));
      }
    }
}

TEST(FuzzySurface, InputsBeyondTheUniverseClampToItsEdge) {
  for (int16_t ec = -900; ec <= 900; ec += 37) {
    const fuzzy::Deltas inside = fuzzy::interpolate<kSurfaceStepShift>(load_host, 768, ec < -768 ? -768 : (ec > 768 ? 768 : ec));
    const fuzzy::Deltas beyond = fuzzy::interpolate<kSurfaceStepShift>(load_host, 2000, ec);
    EXPECT_EQ(inside.dkp_q8, beyond.dkp_q8);
    EXPECT_EQ(inside.dki_q8, beyond.dki_q8);
    EXPECT_EQ(inside.dkd_q8, beyond.dkd_q8);
  }
}

// Max and RMS |interpolated − exact Mamdani| over a dense grid (step 1/32 universe: 8 points
// per cell each way, both signs). Stated bounds, measured: see docs/fuzzy_pid.md. Mamdani
// centroids are rational functions that turn steep where a small output set (the half
// triangles at 0 and 3) dominates and a second rule starts to fire — near e = ±3 above all —
// so the max error is set by a few cells at the universe's edge; the RMS shows the bulk.
TEST(FuzzySurface, InterpolatedSurfacesTrackTheDirectMamdaniEvaluation) {
  const double kMaxBound[3] = {0.40, 0.22, 0.27};
  const double kRmsBound[3] = {0.05, 0.04, 0.04};
  const double kInnerMaxBound = 0.17;  // |e| ≤ 2 (|e| ≤ 5 °C at the default factor 0.4)
  for (int t = 0; t < 3; ++t) {
    double worst = 0, worst_e = 0, worst_ec = 0, inner = 0, sum2 = 0;
    int n = 0;
    for (int a = -96; a <= 96; ++a)
      for (int b = -96; b <= 96; ++b) {
        const int16_t e_q8 = static_cast<int16_t>(a * 8), ec_q8 = static_cast<int16_t>(b * 8);
        const double got = delta_value(fuzzy::interpolate<kSurfaceStepShift>(load_host, e_q8, ec_q8), t) / 256.0;
        const double err = std::fabs(got - mamdani(*kTables[t], e_q8 / 256.0, ec_q8 / 256.0, 1500));
        if (err > worst) { worst = err; worst_e = e_q8 / 256.0; worst_ec = ec_q8 / 256.0; }
        if (std::abs(a) <= 64) inner = std::fmax(inner, err);
        sum2 += err * err;
        ++n;
      }
    const double rms = std::sqrt(sum2 / n);
    std::printf("  %s: max |error| %.4f at (e %.3f, ec %.3f), max for |e|<=2 %.4f, RMS %.4f\n", kNames[t], worst,
                worst_e, worst_ec, inner, rms);
    EXPECT_LE(worst, kMaxBound[t]) << kNames[t];
    EXPECT_LE(rms, kRmsBound[t]) << kNames[t];
    EXPECT_LE(inner, kInnerMaxBound) << kNames[t];
  }
}

}  // namespace
