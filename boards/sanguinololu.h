// Sanguinololu 1.3a/1.4 (ATmega1284P, 16 MHz). Pin facts from the Sanguinololu schematic
// (RepRap wiki) and the ATmega1284P datasheet pinout. Data only.
#pragma once
#include "pin.h"

namespace boards {
namespace sanguinololu {

constexpr const char* kName = "Sanguinololu";
constexpr const char* kMcu = "atmega1284p";
constexpr uint32_t kCpuHz = 16000000UL;

constexpr Pin kHotendHeater{'D', 5};  // HEATER_0, MOSFET gate
constexpr uint8_t kHotendAdcChannel = 7;  // TEMP_0 on PA7/ADC7
constexpr Pin kBedHeater{'D', 4};
constexpr uint8_t kBedAdcChannel = 6;  // TEMP_BED on PA6/ADC6
constexpr Pin kPartFan{'B', 4};
constexpr uint8_t kUart = 0;

// Thermistor front end: 4.7 kOhm pull-up to AVcc, AVcc (5 V) is the ADC reference.
constexpr uint32_t kThermistorPullupOhm = 4700;
constexpr uint16_t kAdcRefMillivolts = 5000;

}  // namespace sanguinololu
}  // namespace boards
