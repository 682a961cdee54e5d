#include "sim/run_setup.h"

#include <filesystem>
#include <stdexcept>

#include "sim/controller_setup.h"
#include "sim/default_gains.h"

namespace sim {

const BoardSpec& board_named(const std::string& id) {
  const BoardSpec* b = find_board(id);
  if (!b) throw std::invalid_argument("unknown board \"" + id + "\" (sanguinololu, ramps14)");
  return *b;
}

const PlantSpec& plant_named(const std::string& name) {
  const PlantSpec* p = find_plant(name);
  if (!p) throw std::invalid_argument("unknown plant \"" + name + "\" (see `hotend-sim list`)");
  return *p;
}

std::string default_elf_path(const std::string& dir, const BoardSpec& board) {
  const std::string path = dir + "/firmware-" + board.id + ".elf";
  if (!std::filesystem::exists(path))
    throw std::runtime_error("no firmware image " + path +
                             " (build it: cmake --build <build dir> --target firmware)");
  return path;
}

void apply_common(const Options& o, RunConfig& c, const std::string& controller) {
  c.noise_lsb = parse_number(o.get("noise-lsb", "0.5"), "--noise-lsb");
  c.seed = static_cast<uint64_t>(parse_number(o.get("seed", "1"), "--seed"));
  c.controller = controller;
  c.gcode.clear();
  c.gains.reset();
  c.gains_source.clear();
  if (!controller.empty()) {
    const ControllerSetup setup = controller_setup(controller, c.plant, c.target_c);
    c.gains = setup.gains;
    c.gains_source = setup.gains_source;
    for (const std::string& line : setup.gcode) c.gcode.push_back(TimedCommand{line, std::nullopt});
  }
  if (o.has("gains")) {
    c.gains = parse_gains(o.get("gains"));
    c.gains_source = "--gains";
  } else if (o.has("gains-rule") || controller.empty()) {
    const GainChoice choice = gains_by_rule(c.plant, o.get("gains-rule", kDefaultGainRule), c.target_c);
    c.gains = choice.gains;
    c.gains_source = choice.description;
  }
  for (const TimedCommand& t : parse_gcode(o.get("gcode"))) c.gcode.push_back(t);
}

}  // namespace sim
