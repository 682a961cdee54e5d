// The hotend's thermistor front end as the firmware's ADC sees it: EPCOS 100k NTC under a
// pull-up divider (double precision, control/thermistor_math.h), Gaussian ADC noise, and the
// conversion of the wanted 10-bit code into the integer millivolts simavr 1.6 takes.
//
// Why the code is chosen first: silicon converts code = round(1024·V/Vref) (datasheet), simavr
// converts floor(mV·1023/Vref) from integer mV. Injecting V itself would read ~0.35 °C high at
// 210 °C. So the model draws the code silicon would produce — round(c + noise) with
// c = 1024·V/Vref — and injects the middle of simavr's millivolt bin for exactly that code.
#pragma once

#include <cstdint>
#include <random>

#include "control/thermistor_math.h"

namespace sim {

constexpr int kAdcMaxCode = 1023;

// Integer millivolts for which simavr's floor(mV·1023/vref_mv) equals `code` (0..1023): the
// middle of that bin, so rounding anywhere in simavr cannot move it to a neighbour.
uint16_t simavr_mv_for_code(int code, uint32_t vref_mv);
// What simavr 1.6 converts (avr_adc.c: reg = mV·0x3ff/vref, clipped to 0x3ff).
int simavr_code_for_mv(uint32_t mv, uint32_t vref_mv);
// Silicon's code for a mean (noise-free, unquantised) code c plus noise in LSB, clipped.
int silicon_code(double mean_code, double noise_lsb);

enum class SensorFault { kNone, kOpen, kShorted };

class ThermistorAdc {
 public:
  ThermistorAdc(const thermistor::Sensor& sensor, double pullup_ohm, double noise_sigma_lsb, uint64_t seed);

  // Ideal mean ADC code (0..1024, unquantised) for a sensor temperature, honouring a fault:
  // open → the pull-up takes the pin to Vref (1024), shorted → 0.
  double mean_code(double temp_c) const;
  // One conversion: the code silicon would return (noise drawn here).
  int sample_code(double temp_c);
  // The same conversion as simavr millivolts for the given reference.
  uint16_t sample_mv(double temp_c, uint32_t vref_mv) {
    return simavr_mv_for_code(sample_code(temp_c), vref_mv);
  }
  // Temperature an ideal converter would report for a (mean) code; NaN outside (0, 1024).
  double temperature_for_code(double code) const;

  void set_fault(SensorFault fault) { fault_ = fault; }
  SensorFault fault() const { return fault_; }
  double noise_sigma_lsb() const { return noise_sigma_lsb_; }

 private:
  thermistor::Sensor sensor_;
  double pullup_ohm_;
  double noise_sigma_lsb_;
  SensorFault fault_ = SensorFault::kNone;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
};

}  // namespace sim
