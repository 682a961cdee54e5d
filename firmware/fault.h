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
  kHeatingFailed,       // watch: heating hard but the temperature does not rise / falls (target not yet reached)
  kRunaway,             // watch: the same after the target had been reached
  kModelHeatingFailed,  // model check: heats less than the model allows (target not yet reached)
  kModelRunaway,        // model check: the same after the target had been reached
  kStuckOn,             // model check: heats more than the heater can (heater stuck on)
  kEmergencyStop,       // M112
};

// The "Error:" line text for a fault ("MINTEMP triggered", Marlin's "Thermal Runaway, system
// stopped! Heater_ID: 0", ...); nullptr for kNone.
const gcode::FlashText* fault_message(Fault fault);
// This firmware's reason, printed on a second Error: line after fault_message; nullptr when the
// first line says it all.
const gcode::FlashText* fault_reason(Fault fault);

}  // namespace firmware
