// The hotend thermistor: which sensor the table is built for, and adc_q6 -> temp_q8.
// adc_q6 = mean 10-bit ADC code x 64; temp_q8 = degC x 256.
#pragma once
#include <stdint.h>

#include "control/thermistor_math.h"
#include "hal/board.h"

namespace firmware {
namespace sensor {

// Build-time choice (issue 2 default): EPCOS B57560G104F 100 kOhm NTC on the board's
// 4.7 kOhm pull-up. thermistor::kSemitec104gt2 is the alternative.
constexpr thermistor::Sensor kHotend = thermistor::kEpcos100k;

// adc_q6 of a noise-free reading at temp_c, from the exact model (no table). For constant
// expressions only: evaluated at run time it would link soft-float code.
constexpr uint16_t adc_q6_at(double temp_c) {
  return static_cast<uint16_t>(
      thermistor::divider_adc_code(thermistor::resistance_ohm(kHotend, temp_c),
                                   static_cast<double>(board::kThermistorPullupOhm)) * 64.0 + 0.5);
}

// Interpolated table lookup (table in program memory, computed by the compiler). Values
// beyond the table clamp to its ends; the safety checks also look at adc_q6 itself.
int32_t adc_q6_to_temp_q8(uint16_t adc_q6);

}  // namespace sensor
}  // namespace firmware
