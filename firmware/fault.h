// The heater faults that latch: once one trips, the heater stays off and targets are refused
// until M999 (which is refused while the cause persists) or a reset.
#pragma once
#include <stdint.h>

#include "firmware/gcode_text.h"

namespace firmware {

enum class Fault : uint8_t {
  kNone,
  kMinTemp,        // reading below MINTEMP or thermistor open
  kMaxTemp,        // reading above MAXTEMP or thermistor shorted
  kHeatingFailed,  // heating but the temperature does not rise (heater or sensor detached)
  kRunaway,        // was at target, fell far below and does not recover
  kEmergencyStop,  // M112
};

// The "Error:" line text for a fault ("MINTEMP triggered", ...); nullptr for kNone.
const gcode::FlashText* fault_message(Fault fault);

}  // namespace firmware
