// What `--fault KIND@T` does to the simulated printer at time T, shared by `run` and `serve`:
// sensor faults act on the thermistor's ADC feed, hardware faults on the plant (HotendRig), the
// others are G-code a host would send.
#pragma once

#include <functional>
#include <string>

#include "sim/fault_outcome.h"
#include "sim/hotend_rig.h"

namespace sim {

void inject_fault(FaultKind kind, HotendRig& rig, const std::function<void(const std::string&)>& send_line);

}  // namespace sim
