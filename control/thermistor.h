// adc_q6 → temp_q8 by interpolating a table the compiler builds from the sensor model
// (thermistor_math.h): never a pasted table. Integer-only at run time: a binary search, then
// one 16×16 multiply with a per-segment slope stored in the table (no division).
#pragma once

#include <stdint.h>

#include "control/fixed.h"
#include "control/thermistor_math.h"

namespace thermistor {

// One breakpoint. Entries are sorted by adc_q6, ascending — hottest first (an NTC to ground
// under a pull-up reads lower as it heats).
struct Entry {
  uint16_t adc_q6;     // mean ADC code × 64 (the key)
  int32_t temp_q8;     // temperature at exactly adc_q6, °C × 256
  uint16_t slope_q11;  // fall of temp_q8 per adc_q6 step up to the next entry, Q11 (≤ 32 q8/step)
};

template <int N> struct Table {
  Entry entry[N];
};

// Table span: a margin beyond the 0–300 °C the accuracy target covers, so that MINTEMP/MAXTEMP
// checks at e.g. 5 °C / 290 °C see real values; beyond it readings clamp to the end entries.
constexpr double kTableColdC = -5.0;
constexpr double kTableHotC = 320.0;
constexpr uint8_t kSlopeShift = 11;
constexpr int kDefaultTableSize = 63;  // 2^6 − 1: six loads per lookup; max error ≈ 0.065 °C (tests)

namespace detail {

// 0 when ok. When !ok it divides by zero, which stops any constant evaluation (the compiler names
// this function in its error); a non-constexpr call would be cleaner but avr-gcc 5.4 rejects it.
constexpr int require_table_fits_entry_fields(bool ok) { return 1 / (ok ? 1 : 0) - 1; }

// Exact temperature (°C) at a mean ADC code (0 < code < 1024).
template <class Real>
constexpr Real temp_c_at_code(const BasicSensor<Real>& s, Real pullup_ohm, Real code) {
  return temperature_c(s, divider_resistance_ohm<Real>(code, pullup_ohm));
}

// |d²T/dcode²|^½: linear interpolation error on a segment of width h is ≈ h²·|T''|/8, so spacing
// breakpoints evenly in ∫|T''|^½ gives every segment the same worst error (the classic
// equidistribution result, e.g. de Boor, "A Practical Guide to Splines", ch. III).
// Analytic chain rule, not finite differences, so 32-bit AVR doubles place the same breakpoints.
template <class Real>
constexpr Real error_density(const BasicSensor<Real>& s, Real pullup_ohm, Real code) {
  const Real n = Real(kAdcCodes);
  const Real l = cxmath::ln<Real>(divider_resistance_ohm<Real>(code, pullup_ohm));  // ln R
  const Real l_x = 1 / code + 1 / (n - code);                              // dL/dcode
  const Real l_xx = 1 / ((n - code) * (n - code)) - 1 / (code * code);     // d²L/dcode²
  const Real y = s.a + s.b * l + s.c * l * l * l;                          // 1/T, T in K
  const Real y_l = s.b + 3 * s.c * l * l;
  const Real y_ll = 6 * s.c * l;
  const Real t_l = -y_l / (y * y);
  const Real t_ll = (2 * y_l * y_l / y - y_ll) / (y * y);
  const Real t_xx = t_ll * l_x * l_x + t_l * l_xx;
  const Real mag = t_xx < 0 ? -t_xx : t_xx;
  return mag > 0 ? cxmath::exp<Real>(cxmath::ln<Real>(mag) / 2) : Real(0);
}

template <class Real> constexpr uint16_t round_u16(Real x) { return static_cast<uint16_t>(x + Real(0.5)); }
template <class Real> constexpr int32_t round_i32(Real x) {
  return static_cast<int32_t>(x < 0 ? x - Real(0.5) : x + Real(0.5));
}

}  // namespace detail

// Builds an N-entry table over [cold_c, hot_c] for a sensor under a pull-up to the ADC reference.
// Breakpoint positions are approximate (equidistributed error, rounded to whole adc_q6 steps);
// each entry's temperature is exact at its own key.
template <int N, class Real>
constexpr Table<N> make_table(const BasicSensor<Real>& sensor, uint32_t pullup_ohm,
                              cxmath::NoDeduce<Real> cold_c = Real(kTableColdC),
                              cxmath::NoDeduce<Real> hot_c = Real(kTableHotC)) {
  static_assert(N >= 2 && N <= 255, "the lookup counts entries in a uint8_t");
  constexpr int kSamples = 256;  // quadrature intervals for the error-density integral
  const Real pullup = static_cast<Real>(pullup_ohm);
  const Real code_lo = divider_adc_code<Real>(resistance_ohm(sensor, hot_c), pullup);
  const Real code_hi = divider_adc_code<Real>(resistance_ohm(sensor, cold_c), pullup);
  const Real width = (code_hi - code_lo) / kSamples;

  Real cumulative[kSamples + 1] = {};  // ∫ density from code_lo, trapezoid rule
  Real previous = detail::error_density(sensor, pullup, code_lo);
  for (int j = 1; j <= kSamples; ++j) {
    const Real current = detail::error_density(sensor, pullup, code_lo + j * width);
    cumulative[j] = cumulative[j - 1] + (previous + current) * width / 2;
    previous = current;
  }

  Table<N> table{};
  int j = 1;
  for (int i = 0; i < N; ++i) {
    const Real goal = cumulative[kSamples] * i / (N - 1);
    while (j < kSamples && cumulative[j] < goal) ++j;
    const Real span = cumulative[j] - cumulative[j - 1];
    const Real frac = span > 0 ? (goal - cumulative[j - 1]) / span : Real(0);
    const Real code = i == 0 ? code_lo : (i == N - 1 ? code_hi : code_lo + (j - 1 + frac) * width);
    uint16_t key = detail::round_u16(code * 64);
    if (i > 0 && key <= table.entry[i - 1].adc_q6) key = table.entry[i - 1].adc_q6 + 1;
    table.entry[i].adc_q6 = key;
    table.entry[i].temp_q8 = detail::round_i32(256 * detail::temp_c_at_code(sensor, pullup, Real(key) / 64));
  }
  for (int i = 0; i + 1 < N; ++i) {
    const Real fall_q8 = static_cast<Real>(table.entry[i].temp_q8 - table.entry[i + 1].temp_q8);
    const Real steps = static_cast<Real>(table.entry[i + 1].adc_q6 - table.entry[i].adc_q6);
    const Real slope = fall_q8 * (1 << kSlopeShift) / steps;
    table.entry[i].slope_q11 = static_cast<uint16_t>(
        detail::round_u16(slope) + detail::require_table_fits_entry_fields(slope >= 0 && slope < 65535));
  }
  return table;
}

// Temperature for a mean ADC reading. `load(i)` returns Entry i, or something convertible to it
// that has the key as `.adc_q6` (a PROGMEM reader in the firmware, an array read on the host).
// Binary search for the last entry at or below adc_q6, reading only keys: ⌈log2(count + 1)⌉
// probes, then one full entry. Best with a reader whose unused fields the compiler can drop
// (firmware/temperature_sensor.cpp: ~350 AVR cycles); avr-libc's volatile pgm_read_* cannot be
// dropped. Readings beyond the ends clamp to the end entries' temperatures.
template <class LoadEntry>
int32_t adc_q6_to_temp_q8(LoadEntry load, uint8_t count, uint16_t adc_q6) {
  uint8_t lo = 0;      // entries [0, lo) are at or below adc_q6 ...
  uint8_t hi = count;  // ... and [hi, count) above it
  while (lo < hi) {
    const uint8_t mid = static_cast<uint8_t>((lo + hi) >> 1);
    if (load(mid).adc_q6 <= adc_q6) {
      lo = static_cast<uint8_t>(mid + 1);
    } else {
      hi = mid;
    }
  }
  if (lo == 0) return Entry(load(0)).temp_q8;  // hotter than the table: its hottest entry
  const Entry below = load(static_cast<uint8_t>(lo - 1));
  if (lo == count) return below.temp_q8;  // colder than (or at) its coldest entry
  const uint16_t steps = static_cast<uint16_t>(adc_q6 - below.adc_q6);
  return below.temp_q8 -
         static_cast<int32_t>(fixed::shr_round(fixed::mul_u16(steps, below.slope_q11), kSlopeShift));
}

}  // namespace thermistor
