// Arduino Mega2560 + RAMPS 1.4 (ATmega2560, 16 MHz). Pin facts from the RAMPS 1.4 schematic
// and the Arduino Mega2560 pin mapping (D10 = PB4, D8 = PH5, D9 = PH6, A13 = ADC13). Data only.
#pragma once
#include "pin.h"

namespace boards {
namespace ramps14 {

constexpr const char* kName = "RAMPS 1.4";
constexpr const char* kMcu = "atmega2560";
constexpr uint32_t kCpuHz = 16000000UL;

constexpr Pin kHotendHeater{'B', 4};  // D10, HEATER_0 MOSFET
constexpr uint8_t kHotendAdcChannel = 13;  // A13, T0
constexpr Pin kBedHeater{'H', 5};  // D8, HEATER_BED MOSFET
constexpr uint8_t kBedAdcChannel = 14;  // A14, T1 header used for the bed
constexpr Pin kPartFan{'H', 6};  // D9, FAN MOSFET
constexpr uint8_t kUart = 0;

// Thermistor front end: 4.7 kOhm pull-up to AVcc, AVcc (5 V) is the ADC reference.
constexpr uint32_t kThermistorPullupOhm = 4700;
constexpr uint16_t kAdcRefMillivolts = 5000;

}  // namespace ramps14
}  // namespace boards
