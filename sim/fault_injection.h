// What `--fault KIND@T` does to the simulated printer at time T, shared by `run` and `serve`:
// sensor faults act on the thermistor's ADC feed, the others are G-code a host would send.
#pragma once

#include <functional>
#include <string>

#include "sim/fault_outcome.h"
#include "sim/sensor.h"

namespace sim {

void inject_fault(FaultKind kind, ThermistorAdc& sensor, const std::function<void(const std::string&)>& send_line);

}  // namespace sim
