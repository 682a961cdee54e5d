// The boot banner hosts expect (Marlin convention): "start" first, then echo lines.
#pragma once

#include "firmware/gcode_output.h"

namespace firmware {

// "start", "echo:Hotend controller <version> on <board>", "echo:<reset cause>".
void print_banner(gcode::Output& out);

}  // namespace firmware
