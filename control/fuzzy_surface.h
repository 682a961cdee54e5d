// Run-time side of the fuzzy supervisor: the defuzzified Δkp/Δki/Δkd surfaces as a grid of
// fixed-point samples, read through a load callback and interpolated bilinearly. Integer-only,
// no AVR header: the firmware keeps the grid in PROGMEM and passes a reader (pgm_read_byte),
// the host passes a plain array reader. The grid itself is built by the compiler from the rule
// tables (fuzzy_surface_gen.h).
//
// Q formats:
//   universe coordinates  e_u_q8, ec_u_q8: int16, universe units × 256, −768…768 (−3…3)
//   stored samples        Cell::d*_q6: uint8, output universe × 64, 0…192 (0…3); ½ LSB = 0.008
//   interpolated outputs  Deltas::d*_q8: uint16, output universe × 256, 0…768
//
// Storage halving: the rule tables are point-symmetric (out[i][j] == out[6−i][6−j], asserted
// by the generator), and so is every defuzzified surface: S(−e, −ec) == S(e, ec). Only the rows
// e ≥ 0 are stored; a negative e is folded by negating both inputs.
#pragma once

#include <stdint.h>

#include "control/fixed.h"

namespace fuzzy {

constexpr int16_t kUniverseMaxQ8 = 3 * 256;  // inputs live on −3…3

// One grid node: the three output surfaces interleaved, so one load call serves all three.
struct Cell {
  uint8_t dkp_q6;
  uint8_t dki_q6;
  uint8_t dkd_q6;
};

struct Deltas {
  uint16_t dkp_q8;  // Δkp on the output universe 0…3, × 256
  uint16_t dki_q8;
  uint16_t dkd_q8;
};

// Grid geometry for a node spacing of 2^kStepShift universe-Q8 units: shift 6 → 0.25 (25×25
// over the full universe), shift 7 → 0.5 (13×13). Spacing divides 1, so every node of the rule
// base (integer universe points) is a grid node and the grid reproduces the rules exactly there.
template <int kStepShift> struct Grid {
  static_assert(kStepShift >= 5 && kStepShift <= 7, "spacing 1/8…1/2 universe unit (weights fit a byte)");
  static constexpr int16_t kStepQ8 = int16_t{1} << kStepShift;
  static constexpr int kCols = 2 * kUniverseMaxQ8 / kStepQ8 + 1;  // ec: −3…3
  static constexpr int kRows = kUniverseMaxQ8 / kStepQ8 + 1;      // e: 0…3 (folded)
  static constexpr int kCells = kRows * kCols;
};

// The firmware's grid: spacing 0.25 → 13 rows × 25 columns × 3 bytes = 975 bytes of flash.
// Halving the spacing costs 4× the flash for half the error: docs/fuzzy_pid.md has the table.
constexpr int kSurfaceStepShift = 6;

using LoadCell = Cell (*)(uint16_t index);  // returns node `index` = row · kCols + col

// 8×8 → 16-bit product: written so avr-gcc emits one MUL (both operands zero-extended bytes).
inline uint16_t mul_u8(uint8_t a, uint8_t b) { return static_cast<uint16_t>(static_cast<uint16_t>(a) * b); }

// The three surfaces at (e_u_q8, ec_u_q8). Inputs outside −768…768 are clamped (the universe's
// shoulder sets make the surfaces flat beyond the ends). Cost: four loads, 12 8×8-bit products
// and 6 16×16-bit products, no division: ~790 AVR cycles measured (docs/fuzzy_pid.md).
template <int kStepShift>
Deltas interpolate(LoadCell load, int16_t e_u_q8, int16_t ec_u_q8) {
  using G = Grid<kStepShift>;
  int16_t e = e_u_q8 < -kUniverseMaxQ8 ? -kUniverseMaxQ8 : (e_u_q8 > kUniverseMaxQ8 ? kUniverseMaxQ8 : e_u_q8);
  int16_t ec = ec_u_q8 < -kUniverseMaxQ8 ? -kUniverseMaxQ8 : (ec_u_q8 > kUniverseMaxQ8 ? kUniverseMaxQ8 : ec_u_q8);
  if (e < 0) {  // point symmetry: S(e, ec) = S(−e, −ec)
    e = static_cast<int16_t>(-e);
    ec = static_cast<int16_t>(-ec);
  }
  const uint16_t ue = static_cast<uint16_t>(e);                     // 0…768
  const uint16_t uec = static_cast<uint16_t>(ec + kUniverseMaxQ8);  // 0…1536
  // Cell index = u >> shift, written as the high byte of u << (8 − shift): avr-gcc does a
  // 16-bit shift by 6 as a loop, but a shift by 8 is a free byte move.
  uint8_t row = static_cast<uint8_t>(static_cast<uint16_t>(ue << (8 - kStepShift)) >> 8);
  uint8_t col = static_cast<uint8_t>(static_cast<uint16_t>(uec << (8 - kStepShift)) >> 8);
  uint8_t fx = static_cast<uint8_t>(ue & (G::kStepQ8 - 1));  // position inside the cell, 0…step
  uint8_t fy = static_cast<uint8_t>(uec & (G::kStepQ8 - 1));
  if (row == G::kRows - 1) { --row; fx = G::kStepQ8; }  // the far edge belongs to the last cell
  if (col == G::kCols - 1) { --col; fy = G::kStepQ8; }
  const uint16_t base = static_cast<uint16_t>(row * G::kCols + col);
  const Cell c00 = load(base), c01 = load(base + 1);
  const Cell c10 = load(base + G::kCols), c11 = load(base + G::kCols + 1);
  const uint8_t gx = static_cast<uint8_t>(G::kStepQ8 - fx), gy = static_cast<uint8_t>(G::kStepQ8 - fy);
  // Along e with 8×8-bit products (sum ≤ 192·128 fits 16 bits), then along ec with 16×16 → 32;
  // Q(6 + 2·shift) → Q8, rounded: first a byte shift (free), then the rest on 16 bits (equal to
  // one rounded shift, since the dropped low byte cannot carry across a multiple of 2^rest).
  // Inlined: as three calls it cost ~100 more AVR cycles per interpolation (simavr).
  auto blend = [=](uint8_t v00, uint8_t v01, uint8_t v10, uint8_t v11) __attribute__((always_inline)) -> uint16_t {
    const uint16_t lo = static_cast<uint16_t>(mul_u8(v00, gx) + mul_u8(v10, fx));  // column col
    const uint16_t hi = static_cast<uint16_t>(mul_u8(v01, gx) + mul_u8(v11, fx));  // col + 1
    const uint32_t v = fixed::mul_u16(lo, gy) + fixed::mul_u16(hi, fy);
    constexpr uint8_t kRest = 2 * kStepShift - 2 - 8;  // 2 for the default grid
    const uint16_t top = static_cast<uint16_t>(v >> 8);
    return kRest == 0 ? top : static_cast<uint16_t>((top + (1u << (kRest > 0 ? kRest - 1 : 0))) >> kRest);
  };
  return Deltas{blend(c00.dkp_q6, c01.dkp_q6, c10.dkp_q6, c11.dkp_q6),
                blend(c00.dki_q6, c01.dki_q6, c10.dki_q6, c11.dki_q6),
                blend(c00.dkd_q6, c01.dkd_q6, c10.dkd_q6, c11.dkd_q6)};
}

}  // namespace fuzzy
