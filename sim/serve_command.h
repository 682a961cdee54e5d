// `hotend-sim serve …`: options → ServeConfig, signal handling, the session's report.
#pragma once

#include <string>
#include <vector>

namespace sim {

int serve_command(const std::vector<std::string>& args);

}  // namespace sim
