// Parsing of hotend-sim's command-line values: --name value options, numbers, gains, the
// timed G-code script and fault specifications. Errors throw std::invalid_argument with a
// message naming the option.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "sim/sim_run.h"

namespace sim {

std::vector<std::string> split(const std::string& text, char separator);
std::string trim(const std::string& s);
double parse_number(const std::string& text, const std::string& what);
// "P,I,D" in Marlin units.
MarlinGains parse_gains(const std::string& text);
// "M301 P1 I2 D3;M106 S255@120" → {"M301 P1 I2 D3", untimed}, {"M106 S255", at 120 s};
// "M108@tune+90": 90 s after the `ok` to --autotune's M303.
std::vector<TimedCommand> parse_gcode(const std::string& text);
// "open@60", "short@60", "hang@60" → config.fault, config.fault_at_s; "open@tune+60" during M303.
void parse_fault(const std::string& text, RunConfig& config);

// --name value / --name=value pairs and bare flags.
struct Options {
  std::map<std::string, std::vector<std::string>> values;  // every occurrence, in order
  std::vector<std::string> flags;
  bool has(const std::string& name) const;
  // The last occurrence wins.
  std::string get(const std::string& name, const std::string& fallback = "") const;
  std::vector<std::string> all(const std::string& name) const;
};
// `flag_names` take no value; every other --name takes the next argument.
Options parse_options(const std::vector<std::string>& args, const std::vector<std::string>& flag_names);
// Throws for any valued option not in `known`.
void reject_unknown(const Options& options, const std::vector<std::string>& known);

}  // namespace sim
