// `hotend-sim bench --faults`: issue 8's detection table, fault × plant × board. Each run heats
// to the target with the plant's own M307 model set (as after M303: the model check is tight)
// or, with --untuned, the firmware's default model, injects a hardware fault (detached
// thermistor, dead heater, heater stuck on, quarter power) and records when the first Error:
// came, when the heater pin went off and how hot the block got.
#pragma once

#include <string>
#include <vector>

#include "sim/cli_args.h"

namespace sim {

int bench_faults(const Options& o, const std::vector<std::string>& boards, const std::vector<std::string>& plants,
                 const std::string& elf_dir);

}  // namespace sim
