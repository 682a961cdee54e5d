// The hotend-sim command line: `run` (default), `bench`, `list`. Parses options into RunConfig /
// bench cases and returns the process exit code.
#pragma once

namespace sim {

int cli_main(int argc, char** argv);

}  // namespace sim
