#include "firmware/fault.h"

namespace firmware {

// Marlin's wording where hosts act on it: OctoPrint and Pronterface match "MINTEMP"/"MAXTEMP"
// and Marlin's exact "Thermal Runaway, system stopped! Heater_ID: 0" / "Heating failed, system
// stopped! Heater_ID: 0" (Marlin's temperature.cpp strings, facts only); the reason follows.
const gcode::FlashText* fault_message(Fault fault) {
  switch (fault) {
    case Fault::kMinTemp: return GCODE_TEXT("MINTEMP triggered");
    case Fault::kMaxTemp: return GCODE_TEXT("MAXTEMP triggered");
    case Fault::kHeatingFailed:
    case Fault::kModelHeatingFailed: return GCODE_TEXT("Heating failed, system stopped! Heater_ID: 0");
    case Fault::kRunaway:
    case Fault::kModelRunaway:
    case Fault::kStuckOn: return GCODE_TEXT("Thermal Runaway, system stopped! Heater_ID: 0");
    case Fault::kEmergencyStop: return GCODE_TEXT("Emergency stop");
    case Fault::kNone: break;
  }
  return nullptr;
}

const gcode::FlashText* fault_reason(Fault fault) {
  switch (fault) {
    case Fault::kHeatingFailed:
    case Fault::kRunaway:
      return GCODE_TEXT("Heating watch: temperature not rising at high heater duty (heater or thermistor loose?); M999 clears");
    case Fault::kModelHeatingFailed:
    case Fault::kModelRunaway:
      return GCODE_TEXT("Model check: hotend heats less than its model (M307) allows (heater dead, thermistor or cartridge loose?); M999 clears");
    case Fault::kStuckOn:
      return GCODE_TEXT("Model check: hotend heats with the heater off (heater stuck on?): switch the power off");
    default: break;
  }
  return nullptr;
}

}  // namespace firmware
