// RunConfig pieces shared by `hotend-sim run` and `hotend-sim bench`: names → boards and plants,
// the default firmware image, and the settings both take (noise, seed, controller, gains, G-code).
#pragma once

#include <string>

#include "sim/board_spec.h"
#include "sim/cli_args.h"
#include "sim/plants.h"
#include "sim/sim_run.h"

namespace sim {

const BoardSpec& board_named(const std::string& id);
const PlantSpec& plant_named(const std::string& name);
// This build's image for the board in `dir`; throws, saying how to build it, when missing.
std::string default_elf_path(const std::string& dir, const BoardSpec& board);

// Needs c.plant and c.target_c. Sets noise, seed, the controller's set-up (controller_setup.h;
// "" = plain M301 gains, as issue 2's runs), gains (--gains P,I,D or --gains-rule override the
// controller's) and appends the --gcode commands after the controller's own.
void apply_common(const Options& o, RunConfig& c, const std::string& controller);

}  // namespace sim
