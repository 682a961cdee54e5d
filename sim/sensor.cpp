#include "sim/sensor.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sim {

int simavr_code_for_mv(uint32_t mv, uint32_t vref_mv) {
  const uint32_t code = mv * 0x3FFu / vref_mv;
  return static_cast<int>(std::min<uint32_t>(code, kAdcMaxCode));
}

uint16_t simavr_mv_for_code(int code, uint32_t vref_mv) {
  code = std::clamp(code, 0, kAdcMaxCode);
  // Bin of `code`: the integers mV with code·vref ≤ mV·1023 < (code+1)·vref.
  const uint32_t lo = (uint32_t(code) * vref_mv + 1022u) / 1023u;  // ceil
  if (code == kAdcMaxCode) return static_cast<uint16_t>(lo);       // simavr clips above
  const uint32_t hi = ((uint32_t(code) + 1u) * vref_mv + 1022u) / 1023u - 1u;
  return static_cast<uint16_t>((lo + hi) / 2u);
}

int silicon_code(double mean_code, double noise_lsb) {
  const double code = std::floor(mean_code + noise_lsb + 0.5);  // round half up
  return static_cast<int>(std::clamp(code, 0.0, double(kAdcMaxCode)));
}

ThermistorAdc::ThermistorAdc(const thermistor::Sensor& sensor, double pullup_ohm, double noise_sigma_lsb,
                             uint64_t seed)
    : sensor_(sensor), pullup_ohm_(pullup_ohm), noise_sigma_lsb_(noise_sigma_lsb), rng_(seed) {}

double ThermistorAdc::mean_code(double temp_c) const {
  switch (fault_) {
    case SensorFault::kOpen:
      return thermistor::kAdcCodes;
    case SensorFault::kShorted:
      return 0.0;
    case SensorFault::kNone:
      break;
  }
  return thermistor::divider_adc_code(thermistor::resistance_ohm(sensor_, temp_c), pullup_ohm_);
}

int ThermistorAdc::sample_code(double temp_c) {
  const double noise = noise_sigma_lsb_ > 0.0 ? noise_sigma_lsb_ * normal_(rng_) : 0.0;
  return silicon_code(mean_code(temp_c), noise);
}

double ThermistorAdc::temperature_for_code(double code) const {
  if (!(code > 0.0 && code < thermistor::kAdcCodes)) return std::numeric_limits<double>::quiet_NaN();
  return thermistor::temperature_c(sensor_, thermistor::divider_resistance_ohm(code, pullup_ohm_));
}

}  // namespace sim
