// `--print-like` (issue 8's no-false-trip run): what a print does to the hotend, as timed G-code
// from the heating start: a target in 190–250 °C that changes every 2–5 minutes and a part fan
// at 0–100 % that changes every 30–120 s, drawn from --seed. The run adds M303 at the start and
// ADC noise (--noise-lsb), and its check is only that nothing trips (no Error:, no reset).
#pragma once

#include <cstdint>
#include <vector>

#include "sim/sim_run.h"

namespace sim {

std::vector<TimedCommand> print_like_gcode(double seconds, uint64_t seed);

}  // namespace sim
