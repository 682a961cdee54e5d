#include "sim/bench_command.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <stdexcept>

#include "sim/bench.h"
#include "sim/bench_faults.h"
#include "sim/controller_setup.h"
#include "sim/report.h"
#include "sim/run_files.h"
#include "sim/run_setup.h"
#include "sim/svg_plot.h"

namespace sim {
namespace {

// A set-up to run on every board × plant: a controller (controller_setup.h) or a --variant's
// hand-made G-code.
constexpr const char* kAutotune = "autotune";  // M303 E0 S<target> U1, then the run

struct Setup {
  std::string label;
  std::string controller;  // "" for a variant
  std::string gcode;       // the variant's untimed G-code
};

std::vector<Setup> setups(const Options& o) {
  std::vector<Setup> out;
  for (const std::string& v : o.all("variant")) {
    const auto eq = v.find('=');
    out.push_back({v.substr(0, eq), "", eq == std::string::npos ? "" : v.substr(eq + 1)});
  }
  if (!out.empty()) return out;
  // --autotune: M303 U1's controller beside the two it picks from (pid+ff, statefb) designed
  // from the plant's own model, and Marlin's M303 (relay + classic Ziegler–Nichols).
  const std::vector<std::string> names = o.has("controllers") ? split(o.get("controllers"), ',')
                                         : o.has("autotune")  ? std::vector<std::string>{kAutotune, "pid+ff", "statefb", "marlin-zn"}
                                                              : controller_names();
  for (const std::string& n : names) out.push_back({n, n, ""});
  return out;
}

std::string csv_path(const std::string& dir, const BenchCase& c) {
  return dir + "/" + c.config.board.id + "-" + c.config.plant.name + (c.variant.empty() ? "" : "-" + c.variant) +
         ".csv";
}

// One SVG per plant: every set-up's run on the first board, labelled by the set-up.
void write_plots(const std::string& dir, const std::vector<BenchCase>& cases, const std::vector<RunResult>& results) {
  std::filesystem::create_directories(dir);
  const std::string board = cases.front().config.board.id;
  std::vector<std::string> plants;
  for (const BenchCase& c : cases)
    if (std::find(plants.begin(), plants.end(), c.config.plant.name) == plants.end())
      plants.push_back(c.config.plant.name);
  for (const std::string& plant : plants) {
    std::vector<PlotSeries> series;
    for (std::size_t i = 0; i < cases.size(); ++i)
      if (cases[i].config.board.id == board && cases[i].config.plant.name == plant && results[i].heating_start_s)
        series.push_back(read_trace_csv(cases[i].config.csv_path, cases[i].variant));
    if (series.empty()) continue;
    write_svg_plot(dir + "/" + plant + ".svg", plant + " on " + board + ": every controller, fan 0 → 100 % step", series);
  }
}

}  // namespace

int bench_command(const std::vector<std::string>& args) {
  const Options o = parse_options(args, {"markdown", "autotune", "faults", "untuned"});
  reject_unknown(o, {"boards", "plants", "controllers", "variant", "target", "fan-step", "seconds", "jobs",
                     "noise-lsb", "seed", "gains", "gains-rule", "gcode", "csv-dir", "plots", "elf-dir", "fault-at",
                     "fault-kinds", "tail"});
  if (o.has("plots") && !o.has("csv-dir")) throw std::invalid_argument("--plots needs --csv-dir");
  std::vector<std::string> boards, plants;
  for (const BoardSpec& b : all_boards()) boards.push_back(b.id);
  for (const PlantSpec& p : plant_bank()) plants.push_back(p.name);
  if (o.has("boards")) boards = split(o.get("boards"), ',');
  if (o.has("plants")) plants = split(o.get("plants"), ',');
  const std::string elf_dir = o.get("elf-dir", HOTEND_SIM_FIRMWARE_DIR);
  if (o.has("csv-dir")) std::filesystem::create_directories(o.get("csv-dir"));
  if (o.has("faults")) return bench_faults(o, boards, plants, elf_dir);

  // Grouped by plant, then board, so a plant's controllers sit together in the table.
  std::vector<BenchCase> cases;
  for (const std::string& plant : plants)
    for (const std::string& board : boards)
      for (const Setup& s : setups(o)) {
        RunConfig c;
        c.board = board_named(board);
        c.plant = plant_named(plant);
        const bool tune = s.controller == kAutotune;
        if (!tune && !s.controller.empty() && !controller_applies(s.controller, c.plant)) continue;
        c.target_c = parse_number(o.get("target", std::to_string(c.plant.default_target_c)), "--target");
        const double fan_s =
            parse_number(o.get("fan-step", std::to_string(c.plant.default_seconds)), "--fan-step");
        const double seconds = fan_s > 0 ? fan_s + c.plant.default_seconds / 2 : c.plant.default_seconds;
        c.seconds = parse_number(o.get("seconds", std::to_string(seconds)), "--seconds");
        c.elf_path = default_elf_path(elf_dir, c.board);
        apply_common(o, c, tune ? "" : s.controller);
        if (tune) {
          c.autotune = AutotuneConfig();
          c.gains.reset();
          c.gains_source.clear();
        }
        const std::vector<TimedCommand> own = parse_gcode(s.gcode);
        c.gcode.insert(c.gcode.begin(), own.begin(), own.end());
        if (fan_s > 0) c.gcode.push_back(TimedCommand{"M106 S255", fan_s});
        BenchCase bc{c, s.label};
        if (o.has("csv-dir")) bc.config.csv_path = csv_path(o.get("csv-dir"), bc);
        cases.push_back(bc);
      }
  if (cases.empty()) throw std::invalid_argument("nothing to run");
  const unsigned jobs = static_cast<unsigned>(parse_number(o.get("jobs", "0"), "--jobs"));
  const auto start = std::chrono::steady_clock::now();
  const std::vector<RunResult> results = run_bench(cases, jobs);
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const bool fan_step = !o.has("fan-step") || parse_number(o.get("fan-step"), "--fan-step") > 0;
  print_bench_table(std::cout, cases, results, o.has("markdown"), fan_step ? "fan step" : "dist.");
  print_bench_notes(std::cout, cases, results);
  std::cerr << "bench: " << cases.size() << " runs in " << format_fixed(wall_s, 0) << " s wall\n";
  if (o.has("plots")) write_plots(o.get("plots"), cases, results);
  return 0;
}

}  // namespace sim
