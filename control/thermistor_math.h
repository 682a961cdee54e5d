// Exact NTC thermistor and divider models in double precision, all constexpr: the compiler uses
// them to build the firmware's lookup tables (thermistor.h), the simulator uses them to turn a
// plant temperature into an ADC voltage, and the host tests use them as the reference.
// Never call these at run time in the firmware: avr-gcc would link soft-float routines.
#pragma once

#include "control/constexpr_math.h"

namespace thermistor {

constexpr double kZeroCelsiusK = 273.15;  // 0 °C in kelvin (SI definition)

// Steinhart–Hart model: 1/T = a + b·ln R + c·(ln R)³, T in kelvin, R in ohms
// (J.S. Steinhart, S.R. Hart, Deep-Sea Research 15 (1968) 497). The β model is the case c = 0.
struct Sensor {
  double a;  // 1/K
  double b;  // 1/K per ln(Ω)
  double c;  // 1/K per ln(Ω)³; must be ≥ 0 (true of real fits) so that R(T) is monotonic
};

// Steinhart–Hart coefficients through three (°C, Ω) points: the 3×3 linear system in
// (a, b, c) solved in closed form by elimination (the usual textbook solution).
constexpr Sensor steinhart_hart_fit(double t1_c, double r1_ohm, double t2_c, double r2_ohm,
                                    double t3_c, double r3_ohm) {
  const double l1 = cxmath::ln(r1_ohm), l2 = cxmath::ln(r2_ohm), l3 = cxmath::ln(r3_ohm);
  const double y1 = 1.0 / (t1_c + kZeroCelsiusK), y2 = 1.0 / (t2_c + kZeroCelsiusK),
               y3 = 1.0 / (t3_c + kZeroCelsiusK);
  const double g2 = (y2 - y1) / (l2 - l1);
  const double g3 = (y3 - y1) / (l3 - l1);
  const double c = (g3 - g2) / (l3 - l2) / (l1 + l2 + l3);
  const double b = g2 - c * (l1 * l1 + l1 * l2 + l2 * l2);
  const double a = y1 - (b + c * l1 * l1) * l1;
  return Sensor{a, b, c};
}

// β model R = R0·exp(β(1/T − 1/T0)) rewritten as Steinhart–Hart with c = 0.
constexpr Sensor beta_model(double t0_c, double r0_ohm, double beta_k) {
  return Sensor{1.0 / (t0_c + kZeroCelsiusK) - cxmath::ln(r0_ohm) / beta_k, 1.0 / beta_k, 0.0};
}

// EPCOS (TDK) B57560G104F, 100 kΩ at 25 °C: three points from the maker's R/T table
// (R/T characteristic 8016): 25 °C 100 kΩ, 150 °C 1641.9 Ω, 250 °C 226.15 Ω.
constexpr Sensor kEpcos100k = steinhart_hart_fit(25.0, 100000.0, 150.0, 1641.9, 250.0, 226.15);

// Semitec 104GT-2 (ATC Semitec datasheet): R25 = 100 kΩ, β(25/85) = 4267 K.
constexpr Sensor kSemitec104gt2 = beta_model(25.0, 100000.0, 4267.0);

// Temperature (°C) of the sensor at a resistance (Ω > 0): the Steinhart–Hart equation itself.
constexpr double temperature_c(const Sensor& s, double resistance_ohm) {
  const double l = cxmath::ln(resistance_ohm);
  return 1.0 / (s.a + s.b * l + s.c * l * l * l) - kZeroCelsiusK;
}

// Resistance (Ω) at a temperature (°C): the exact inverse of temperature_c. Solves the cubic
// c·y³ + b·y + (a − 1/T) = 0 for y = ln R by Newton's method: with b > 0, c ≥ 0 the cubic is
// strictly increasing, so the root is unique; starting from the β solution (c = 0) Newton
// converges in a handful of steps. The cap bounds the loop on 32-bit AVR doubles too.
constexpr double resistance_ohm(const Sensor& s, double temp_c) {
  const double d = s.a - 1.0 / (temp_c + kZeroCelsiusK);
  double y = -d / s.b;
  for (int i = 0; i < 40; ++i) {
    const double f = (s.c * y * y + s.b) * y + d;
    const double slope = 3.0 * s.c * y * y + s.b;
    const double step = f / slope;
    y -= step;
    if (cxmath::abs(step) <= 1e-15 * cxmath::abs(y)) break;
  }
  return cxmath::exp(y);
}

// --- The thermistor divider: pull-up from Vref to the ADC pin, thermistor from the pin to ground.
constexpr double kAdcCodes = 1024.0;  // 10-bit ADC, silicon model code = 1024·V/Vref (AVR datasheet)

// Ideal (noise-free, unquantised) mean ADC code for a thermistor resistance: 1024·R/(R + Rpullup).
constexpr double divider_adc_code(double resistance_ohm, double pullup_ohm) {
  return kAdcCodes * resistance_ohm / (resistance_ohm + pullup_ohm);
}

// Inverse of divider_adc_code: thermistor resistance for a mean ADC code in (0, 1024).
constexpr double divider_resistance_ohm(double adc_code, double pullup_ohm) {
  return pullup_ohm * adc_code / (kAdcCodes - adc_code);
}

}  // namespace thermistor
