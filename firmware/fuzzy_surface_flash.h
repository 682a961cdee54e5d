// The fuzzy-PID's defuzzified surfaces in program memory (975 bytes, built by the compiler from
// the rule tables) and the reader control::FuzzyPid is given.
#pragma once
#include <stdint.h>

#include "control/fuzzy_surface.h"

namespace firmware {

// Grid node `index` (row · columns + column) from flash.
fuzzy::Cell load_surface_cell(uint16_t index);

}  // namespace firmware
