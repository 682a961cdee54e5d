// The host's reader of control/state_feedback_gcode.h's field runs; the images read their flash
// copy (firmware/state_feedback_runs_flash.cpp).
#include "control/state_feedback_gcode.h"

namespace control {

SfRun sf_run(uint8_t i) { return kSfRuns.run[i]; }

}  // namespace control
