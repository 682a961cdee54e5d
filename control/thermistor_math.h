// Exact NTC thermistor and divider models, all constexpr: the compiler uses them to build the
// firmware's lookup tables (thermistor.h), the simulator turns plant temperatures into ADC
// voltages with them, and the host tests use them as the reference.
// Never call these at run time in the firmware: avr-gcc would link soft-float routines.
// Templates on the floating type only so the host can replay avr-gcc's 32-bit `double`
// (see constexpr_math.h); everyday use is the double API: Sensor, kEpcos100k, resistance_ohm(...).
#pragma once

#include "control/constexpr_math.h"

namespace thermistor {

constexpr double kZeroCelsiusK = 273.15;  // 0 °C in kelvin (SI definition)

// Steinhart–Hart model: 1/T = a + b·ln R + c·(ln R)³, T in kelvin, R in ohms
// (J.S. Steinhart, S.R. Hart, Deep-Sea Research 15 (1968) 497). The β model is the case c = 0.
template <class Real> struct BasicSensor {
  Real a;  // 1/K
  Real b;  // 1/K per ln(Ω); > 0 for an NTC
  Real c;  // 1/K per ln(Ω)³; ≥ 0 for real fits, which keeps R(T) monotonic
};
using Sensor = BasicSensor<double>;

// Steinhart–Hart coefficients through three (°C, Ω) points: the 3×3 linear system in
// (a, b, c) solved in closed form by elimination (the usual textbook solution).
template <class Real = double>
constexpr BasicSensor<Real> steinhart_hart_fit(cxmath::NoDeduce<Real> t1_c, cxmath::NoDeduce<Real> r1_ohm,
                                               cxmath::NoDeduce<Real> t2_c, cxmath::NoDeduce<Real> r2_ohm,
                                               cxmath::NoDeduce<Real> t3_c, cxmath::NoDeduce<Real> r3_ohm) {
  const Real l1 = cxmath::ln<Real>(r1_ohm), l2 = cxmath::ln<Real>(r2_ohm), l3 = cxmath::ln<Real>(r3_ohm);
  const Real y1 = 1 / (t1_c + Real(kZeroCelsiusK)), y2 = 1 / (t2_c + Real(kZeroCelsiusK)),
             y3 = 1 / (t3_c + Real(kZeroCelsiusK));
  const Real g2 = (y2 - y1) / (l2 - l1);
  const Real g3 = (y3 - y1) / (l3 - l1);
  const Real c = (g3 - g2) / (l3 - l2) / (l1 + l2 + l3);
  const Real b = g2 - c * (l1 * l1 + l1 * l2 + l2 * l2);
  const Real a = y1 - (b + c * l1 * l1) * l1;
  return BasicSensor<Real>{a, b, c};
}

// β model R = R0·exp(β(1/T − 1/T0)) rewritten as Steinhart–Hart with c = 0.
template <class Real = double>
constexpr BasicSensor<Real> beta_model(cxmath::NoDeduce<Real> t0_c, cxmath::NoDeduce<Real> r0_ohm,
                                       cxmath::NoDeduce<Real> beta_k) {
  const Real a = 1 / (t0_c + Real(kZeroCelsiusK)) - cxmath::ln<Real>(r0_ohm) / beta_k;
  return BasicSensor<Real>{a, 1 / beta_k, 0};
}

// EPCOS (TDK) B57560G104F, 100 kΩ at 25 °C, three points of the maker's R/T table
// (characteristic 8016): 25 °C 100 kΩ, 150 °C 1641.9 Ω, 250 °C 226.15 Ω.
template <class Real = double> constexpr BasicSensor<Real> epcos100k() {
  return steinhart_hart_fit<Real>(25, 100000, 150, Real(1641.9), 250, Real(226.15));
}
constexpr Sensor kEpcos100k = epcos100k();

// Semitec 104GT-2 (ATC Semitec 104GT datasheet): R25 = 100 kΩ, β(25/85) = 4267 K.
template <class Real = double> constexpr BasicSensor<Real> semitec104gt2() {
  return beta_model<Real>(25, 100000, 4267);
}
constexpr Sensor kSemitec104gt2 = semitec104gt2();

// Temperature (°C) of the sensor at a resistance (Ω > 0): the Steinhart–Hart equation itself.
template <class Real>
constexpr Real temperature_c(const BasicSensor<Real>& s, cxmath::NoDeduce<Real> resistance_ohm) {
  const Real l = cxmath::ln<Real>(resistance_ohm);
  return 1 / (s.a + s.b * l + s.c * l * l * l) - Real(kZeroCelsiusK);
}

// Resistance (Ω) at a temperature (°C): the exact inverse of temperature_c. Solves the cubic
// c·y³ + b·y + (a − 1/T) = 0 for y = ln R by Newton's method: with b > 0, c ≥ 0 the cubic is
// strictly increasing, so the root is unique; starting from the β solution (c = 0) Newton
// converges in a handful of steps. The cap bounds the loop with 32-bit AVR doubles too.
template <class Real>
constexpr Real resistance_ohm(const BasicSensor<Real>& s, cxmath::NoDeduce<Real> temp_c) {
  const Real d = s.a - 1 / (temp_c + Real(kZeroCelsiusK));
  Real y = -d / s.b;
  for (int i = 0; i < 40; ++i) {
    const Real f = (s.c * y * y + s.b) * y + d;
    const Real step = f / (3 * s.c * y * y + s.b);
    y -= step;
    if (cxmath::abs<Real>(step) <= Real(1e-15) * cxmath::abs<Real>(y)) break;
  }
  return cxmath::exp<Real>(y);
}

// --- The divider: pull-up from Vref to the ADC pin, thermistor from the pin to ground.
constexpr double kAdcCodes = 1024.0;  // 10-bit ADC, code = 1024·V/Vref (AVR datasheet, ADC section)

// Ideal (noise-free, unquantised) mean ADC code for a thermistor resistance: 1024·R/(R + Rpullup).
template <class Real = double>
constexpr Real divider_adc_code(cxmath::NoDeduce<Real> resistance_ohm, cxmath::NoDeduce<Real> pullup_ohm) {
  return Real(kAdcCodes) * resistance_ohm / (resistance_ohm + pullup_ohm);
}

// Inverse of divider_adc_code: thermistor resistance for a mean ADC code in (0, 1024).
template <class Real = double>
constexpr Real divider_resistance_ohm(cxmath::NoDeduce<Real> adc_code, cxmath::NoDeduce<Real> pullup_ohm) {
  return pullup_ohm * adc_code / (Real(kAdcCodes) - adc_code);
}

}  // namespace thermistor
