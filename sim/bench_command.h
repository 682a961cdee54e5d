// `hotend-sim bench`: every controller × board × plant with a part-fan step, one table, and
// optionally the traces (CSV) and one plot per plant. Usage in cli.cpp.
#pragma once

#include <string>
#include <vector>

namespace sim {

// Returns the process exit code; throws std::invalid_argument for bad options.
int bench_command(const std::vector<std::string>& args);

}  // namespace sim
