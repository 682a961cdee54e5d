#include "sim/cli.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/bench.h"
#include "sim/cli_args.h"
#include "sim/default_gains.h"
#include "sim/report.h"
#include "sim/run_files.h"
#include "sim/sim_run.h"
#include "sim/svg_plot.h"

namespace sim {
namespace {

constexpr double kFaultRunTailS = 5.0;  // fault runs end this long after the fault by default

const char* const kUsage = R"(usage:
  hotend-sim [run] [--board sanguinololu|ramps14] [--plant NAME] [--target C] [--seconds S]
             [--csv FILE] [--noise-lsb SIGMA] [--seed N] [--gains P,I,D | --gains-rule RULE]
             [--gcode "CMD;CMD@T"] [--elf FILE] [--fault open@T|short@T|hang@T] [--check]
             [--max-overshoot C] [--max-steady-error C] [--max-report-error C]
             [--max-steady-p2p C] [--transcript FILE] [--quiet]
  hotend-sim bench [--markdown] [--boards a,b] [--plants x,y] [--target C] [--seconds S]
             [--jobs N] [--noise-lsb SIGMA] [--seed N] [--gains P,I,D | --gains-rule RULE]
             [--gcode "CMD@T"] [--variant NAME=GCODE]... [--csv-dir DIR] [--elf-dir DIR]
  hotend-sim list
  hotend-sim plot --out FILE.svg [--title TEXT] RUN.csv...

run: boots the firmware ELF in simavr on the plant, sends M301 (gains), the untimed --gcode
  commands, M155 S1 and M104 S<target>; the heating start t0 is the firmware's `ok` to M104 and
  --seconds counts from there. Commands with @T are sent T s after t0; the first one splits the
  run: quality metrics before it, disturbance metrics (max |error|, recovery) after it.
  Defaults: ramps14, hotend40w, the plant's own target/duration, noise σ 0.5 LSB, gains from
  the plant's FOPDT approximation by --gains-rule (simc = SIMC PI with τc = 2τ; also
  simc-tight, amigo, cohen-coon, zn-step on that fit, and zn-relay: M303's relay experiment
  with classic Ziegler–Nichols; see `list`), ELF from this build's firmware directory.
  --fault: thermistor open/short or a D0 hang T s after t0; the run ends 5 s after it.
  --check: exit 1 (listing what failed) unless the run meets the HIL limits: reaches ±1 °C,
  overshoot ≤ 5 °C, |steady mean error| ≤ 0.5 °C, T: reports within 1 °C of the true
  temperature, no Error: line or reset, back in ±1 °C after a timed command (all adjustable);
  fault runs: heater off within 1 s and the Error: line, or for a hang reset + start + off.
  --transcript: the serial conversation with simulated times ("> " sent, "< " received).
bench: every board × plant (or the given ones) in parallel, at each plant's default target and
  duration (or --target/--seconds for all); prints one table (with disturbance columns when
  --gcode has a timed command) and under it every problem or Error: line. Each --variant runs
  the grid again with its untimed G-code (e.g. a controller choice or its own M301).
plot: temperature and heater duty of several --csv runs against time in one SVG.
)";

// This build's image for the board; says how to make it when it is missing.
std::string default_elf_path(const std::string& dir, const BoardSpec& board) {
  const std::string path = dir + "/firmware-" + board.id + ".elf";
  if (!std::filesystem::exists(path))
    throw std::runtime_error("no firmware image " + path +
                             " (build it: cmake --build <build dir> --target firmware)");
  return path;
}

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

// Settings shared by `run` and `bench`: noise, seed, gains, G-code.
void apply_common(const Options& o, RunConfig& c) {
  c.noise_lsb = parse_number(o.get("noise-lsb", "0.5"), "--noise-lsb");
  c.seed = static_cast<uint64_t>(parse_number(o.get("seed", "1"), "--seed"));
  if (o.has("gains")) {
    c.gains = parse_gains(o.get("gains"));
    c.gains_source = "--gains";
  } else {
    const GainChoice choice = gains_by_rule(c.plant, o.get("gains-rule", kDefaultGainRule), c.target_c);
    c.gains = choice.gains;
    c.gains_source = choice.description;
  }
  c.gcode = parse_gcode(o.get("gcode"));
}

int run_command(const std::vector<std::string>& args) {
  const Options o = parse_options(args, {"check", "quiet"});
  reject_unknown(o, {"board", "plant", "target", "seconds", "csv", "noise-lsb", "seed", "gains", "gains-rule",
                     "gcode", "elf", "fault", "transcript", "max-overshoot", "max-steady-error",
                     "max-report-error", "max-steady-p2p"});
  RunConfig c;
  c.board = board_named(o.get("board", "ramps14"));
  c.plant = plant_named(o.get("plant", "hotend40w"));
  c.target_c = parse_number(o.get("target", std::to_string(c.plant.default_target_c)), "--target");
  if (o.has("fault")) parse_fault(o.get("fault"), c);
  const double default_seconds =
      c.fault == FaultKind::kNone ? c.plant.default_seconds : c.fault_at_s + kFaultRunTailS;
  c.seconds = parse_number(o.get("seconds", std::to_string(default_seconds)), "--seconds");
  c.csv_path = o.get("csv");
  c.elf_path = o.has("elf") ? o.get("elf") : default_elf_path(HOTEND_SIM_FIRMWARE_DIR, c.board);
  apply_common(o, c);

  CheckLimits limits;
  limits.max_overshoot_c = parse_number(o.get("max-overshoot", "5"), "--max-overshoot");
  limits.max_steady_error_c = parse_number(o.get("max-steady-error", "0.5"), "--max-steady-error");
  limits.max_report_error_c = parse_number(o.get("max-report-error", "1"), "--max-report-error");
  if (o.has("max-steady-p2p"))
    limits.max_steady_peak_to_peak_c = parse_number(o.get("max-steady-p2p"), "--max-steady-p2p");

  const RunResult result = run_simulation(c);
  if (!o.has("quiet")) print_report(std::cout, result);
  if (o.has("transcript")) write_transcript(o.get("transcript"), result.transcript);
  if (!o.has("check")) return 0;
  const std::vector<std::string> failed = failed_checks(result, limits);
  for (const std::string& f : failed) std::cout << "CHECK FAILED: " << f << "\n";
  if (failed.empty()) std::cout << "CHECK PASSED\n";
  return failed.empty() ? 0 : 1;
}

int bench_command(const std::vector<std::string>& args) {
  const Options o = parse_options(args, {"markdown"});
  reject_unknown(o, {"boards", "plants", "target", "seconds", "jobs", "noise-lsb", "seed", "gains",
                     "gains-rule", "gcode", "variant", "csv-dir", "elf-dir"});
  std::vector<std::string> boards, plants;
  for (const BoardSpec& b : all_boards()) boards.push_back(b.id);
  for (const PlantSpec& p : plant_bank()) plants.push_back(p.name);
  if (o.has("boards")) boards = split(o.get("boards"), ',');
  if (o.has("plants")) plants = split(o.get("plants"), ',');
  const std::string elf_dir = o.get("elf-dir", HOTEND_SIM_FIRMWARE_DIR);

  // --variant NAME=GCODE (repeatable): the same board × plant grid once per variant, with the
  // variant's untimed G-code sent after the gains (e.g. a controller choice or its own M301).
  std::vector<std::pair<std::string, std::string>> variants{{"", ""}};
  if (o.has("variant")) variants.clear();
  for (const std::string& v : o.all("variant")) {
    const auto eq = v.find('=');
    variants.emplace_back(v.substr(0, eq), eq == std::string::npos ? "" : v.substr(eq + 1));
  }

  std::vector<BenchCase> cases;
  for (const auto& [variant, variant_gcode] : variants)
    for (const std::string& board : boards)
      for (const std::string& plant : plants) {
        RunConfig c;
        c.board = board_named(board);
        c.plant = plant_named(plant);
        c.target_c = parse_number(o.get("target", std::to_string(c.plant.default_target_c)), "--target");
        c.seconds = parse_number(o.get("seconds", std::to_string(c.plant.default_seconds)), "--seconds");
        c.elf_path = default_elf_path(elf_dir, c.board);
        apply_common(o, c);
        const std::vector<TimedCommand> extra = parse_gcode(variant_gcode);
        c.gcode.insert(c.gcode.begin(), extra.begin(), extra.end());
        if (o.has("csv-dir"))
          c.csv_path =
              o.get("csv-dir") + "/" + board + "-" + plant + (variant.empty() ? "" : "-" + variant) + ".csv";
        cases.push_back(BenchCase{c, variant});
      }
  const unsigned jobs = static_cast<unsigned>(parse_number(o.get("jobs", "0"), "--jobs"));
  const std::vector<RunResult> results = run_bench(cases, jobs);
  print_bench_table(std::cout, cases, results, o.has("markdown"));
  print_bench_notes(std::cout, cases, results);
  return 0;
}

// hotend-sim plot --out FILE.svg [--title T] RUN.csv...: labels are the file names' stems.
int plot_command(const std::vector<std::string>& args) {
  std::vector<std::string> csvs, rest;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i].rfind("--", 0) == 0) {
      rest.push_back(args[i]);
      if (i + 1 < args.size() && args[i].find('=') == std::string::npos) rest.push_back(args[++i]);
    } else {
      csvs.push_back(args[i]);
    }
  }
  const Options o = parse_options(rest, {});
  reject_unknown(o, {"out", "title"});
  if (!o.has("out") || csvs.empty()) throw std::invalid_argument("plot wants --out FILE.svg and CSV files");
  std::vector<PlotSeries> series;
  for (const std::string& csv : csvs)
    series.push_back(read_trace_csv(csv, std::filesystem::path(csv).stem()));
  write_svg_plot(o.get("out"), o.get("title", "hotend-sim runs"), series);
  return 0;
}

int list_command() {
  std::cout << "boards:\n";
  for (const BoardSpec& b : all_boards())
    std::cout << "  " << b.id << "  " << b.name << " (" << b.mcu << "), heater P" << b.hotend_heater.port
              << int(b.hotend_heater.bit) << ", fan P" << b.part_fan.port << int(b.part_fan.bit)
              << ", thermistor ADC" << int(b.hotend_adc_channel) << "\n";
  std::cout << "plants:\n";
  for (const PlantSpec& p : plant_bank()) {
    const GainChoice g = gains_by_rule(p, kDefaultGainRule, p.default_target_c);
    const PhysicalBound b = physical_bound(p, p.default_target_c);
    std::cout << "  " << p.name << "  " << p.description << "\n"
              << "      100 % settles " << format_fixed(p.model.dc_gain_k(), 1) << " K above ambient ("
              << format_fixed(p.model.dc_gain_k(1.0), 1) << " with the fan); default "
              << format_fixed(p.default_target_c, 0) << " °C for " << format_fixed(p.default_seconds, 0)
              << " s, physical bound " << format_fixed(b.settling_s, 1) << " s\n"
              << "      default gains P " << format_fixed(g.gains.kp, 3) << " I "
              << format_fixed(g.gains.ki, 4) << " D " << format_fixed(g.gains.kd, 2) << " (" << g.description
              << ")\n";
  }
  return 0;
}

}  // namespace

int cli_main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  for (const std::string& a : args)
    if (a == "--help" || a == "-h") {
      std::cout << kUsage;
      return 0;
    }
  std::string command = "run";
  if (!args.empty() && args[0].rfind("--", 0) != 0) {
    command = args[0];
    args.erase(args.begin());
  }
  try {
    if (command == "run") return run_command(args);
    if (command == "bench") return bench_command(args);
    if (command == "list") return list_command();
    if (command == "plot") return plot_command(args);
    if (command == "help") {
      std::cout << kUsage;
      return 0;
    }
    throw std::invalid_argument("unknown command \"" + command + "\"");
  } catch (const std::invalid_argument& e) {
    std::cerr << "hotend-sim: " << e.what() << "\n(hotend-sim --help shows the usage)\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "hotend-sim: " << e.what() << "\n";
    return 2;
  }
}

}  // namespace sim
