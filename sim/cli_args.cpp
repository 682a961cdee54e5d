#include "sim/cli_args.h"

#include <algorithm>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace sim {

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  for (std::string part; std::getline(in, part, separator);) parts.push_back(part);
  return parts;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  const auto e = s.find_last_not_of(" \t");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

double parse_number(const std::string& text, const std::string& what) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0') throw std::invalid_argument(what + ": not a number: \"" + text + "\"");
  return v;
}

MarlinGains parse_gains(const std::string& text) {
  const std::vector<std::string> parts = split(text, ',');
  if (parts.size() != 3) throw std::invalid_argument("--gains wants P,I,D");
  return MarlinGains{parse_number(parts[0], "--gains P"), parse_number(parts[1], "--gains I"),
                     parse_number(parts[2], "--gains D")};
}

std::vector<TimedCommand> parse_gcode(const std::string& text) {
  std::vector<TimedCommand> commands;
  for (const std::string& item : split(text, ';')) {
    std::string line = trim(item);
    if (line.empty()) continue;
    TimedCommand c;
    const auto at = line.rfind('@');
    if (at != std::string::npos) {
      std::string when = trim(line.substr(at + 1));
      if (when.rfind("tune+", 0) == 0) {  // "M108@tune+120": 120 s after M303 was acknowledged
        c.in_tune = true;
        when = when.substr(5);
      }
      c.at_s = parse_number(when, "--gcode time");
      line = trim(line.substr(0, at));
    }
    c.line = line;
    commands.push_back(c);
  }
  return commands;
}

void parse_fault(const std::string& text, RunConfig& config) {
  const auto at = text.find('@');
  if (at == std::string::npos) throw std::invalid_argument("--fault wants KIND@SECONDS");
  const std::string kind = text.substr(0, at);
  if (kind == "open")
    config.fault = FaultKind::kOpen;
  else if (kind == "short")
    config.fault = FaultKind::kShort;
  else if (kind == "hang")
    config.fault = FaultKind::kHang;
  else if (kind == "m108")
    config.fault = FaultKind::kM108;
  else if (kind == "m112")
    config.fault = FaultKind::kM112;
  else if (kind == "m112-wait")
    config.fault = FaultKind::kM112Wait;
  else if (kind == "m112-burst")
    config.fault = FaultKind::kM112Burst;
  else if (kind == "overrun")
    config.fault = FaultKind::kOverrun;
  else if (kind == "overrun-numbered")
    config.fault = FaultKind::kOverrunNumbered;
  else if (kind == "detached")
    config.fault = FaultKind::kDetached;
  else if (kind == "heater-dead")
    config.fault = FaultKind::kHeaterDead;
  else if (kind == "stuck-on")
    config.fault = FaultKind::kStuckOn;
  else if (kind == "quarter-power")
    config.fault = FaultKind::kQuarterPower;
  else if (kind == "fan-stuck")
    config.fault = FaultKind::kFanStuck;
  else
    throw std::invalid_argument("--fault: unknown kind \"" + kind +
                                "\" (open, short, hang, m108, m112, m112-wait, m112-burst, overrun, overrun-numbered, detached, heater-dead, stuck-on, "
                                "quarter-power, fan-stuck)");
  std::string when = text.substr(at + 1);
  config.fault_in_tune = when.rfind("tune+", 0) == 0;  // "open@tune+60": during M303
  if (config.fault_in_tune) when = when.substr(5);
  config.fault_at_s = parse_number(when, "--fault time");
}

bool Options::has(const std::string& name) const {
  return values.count(name) || std::find(flags.begin(), flags.end(), name) != flags.end();
}

std::string Options::get(const std::string& name, const std::string& fallback) const {
  auto it = values.find(name);
  return it == values.end() ? fallback : it->second.back();
}

std::vector<std::string> Options::all(const std::string& name) const {
  auto it = values.find(name);
  return it == values.end() ? std::vector<std::string>{} : it->second;
}

Options parse_options(const std::vector<std::string>& args, const std::vector<std::string>& flag_names) {
  Options o;
  for (std::size_t i = 0; i < args.size(); ++i) {
    std::string name = args[i];
    if (name.rfind("--", 0) != 0) throw std::invalid_argument("unexpected argument \"" + name + "\"");
    name = name.substr(2);
    const auto eq = name.find('=');
    if (eq != std::string::npos) {
      o.values[name.substr(0, eq)].push_back(name.substr(eq + 1));
    } else if (std::find(flag_names.begin(), flag_names.end(), name) != flag_names.end()) {
      o.flags.push_back(name);
    } else {
      if (i + 1 >= args.size()) throw std::invalid_argument("--" + name + " needs a value");
      o.values[name].push_back(args[++i]);
    }
  }
  return o;
}

void reject_unknown(const Options& o, const std::vector<std::string>& known) {
  for (const auto& [name, value] : o.values)
    if (std::find(known.begin(), known.end(), name) == known.end())
      throw std::invalid_argument("unknown option --" + name);
}

}  // namespace sim
