#include "firmware/fault.h"

namespace firmware {

// Marlin's wording where hosts act on it (OctoPrint matches "MINTEMP"/"MAXTEMP" and
// "Thermal Runaway"); the rest says what happened and how to clear it.
const gcode::FlashText* fault_message(Fault fault) {
  switch (fault) {
    case Fault::kMinTemp: return GCODE_TEXT("MINTEMP triggered");
    case Fault::kMaxTemp: return GCODE_TEXT("MAXTEMP triggered");
    case Fault::kHeatingFailed: return GCODE_TEXT("Heating failed: temperature not rising");
    case Fault::kRunaway: return GCODE_TEXT("Thermal Runaway: temperature fell and stays low");
    case Fault::kEmergencyStop: return GCODE_TEXT("Emergency stop");
    case Fault::kNone: break;
  }
  return nullptr;
}

}  // namespace firmware
