#include "sim/bench_faults.h"

#include <chrono>
#include <iostream>

#include "sim/bench.h"
#include "sim/bound.h"
#include "sim/report.h"
#include "sim/run_setup.h"

namespace sim {
namespace {

struct FaultName {
  const char* name;
  FaultKind kind;
};
const FaultName kFaults[] = {{"detached", FaultKind::kDetached},
                             {"heater-dead", FaultKind::kHeaterDead},
                             {"stuck-on", FaultKind::kStuckOn},
                             {"quarter-power", FaultKind::kQuarterPower}};

// When the fault comes: "hold" = at the target (the heat-up's physical bound × 1.5 + 30 s, so
// the controller has settled), "half" = halfway through the heat-up (half the bound's switch time).
double fault_time_s(const PlantSpec& plant, double target_c, const std::string& when) {
  const PhysicalBound b = physical_bound(plant, target_c);
  if (when == "half") return 0.5 * b.switch_s;
  return 1.5 * b.settling_s + 30.0;
}

std::string cell(const std::optional<double>& v, int decimals) { return v ? format_fixed(*v, decimals) : "-"; }

}  // namespace

int bench_faults(const Options& o, const std::vector<std::string>& boards, const std::vector<std::string>& plants,
                 const std::string& elf_dir) {
  const std::string when = o.get("fault-at", "hold");
  if (when != "hold" && when != "half") throw std::invalid_argument("--fault-at wants hold or half");
  const bool untuned = o.has("untuned");
  std::vector<std::string> faults;
  for (const FaultName& f : kFaults) faults.push_back(f.name);
  if (o.has("fault-kinds")) faults = split(o.get("fault-kinds"), ',');
  std::vector<BenchCase> cases;
  for (const std::string& fault : faults)
    for (const std::string& plant : plants)
      for (const std::string& board : boards) {
        RunConfig c;
        c.board = board_named(board);
        c.plant = plant_named(plant);
        c.target_c = parse_number(o.get("target", std::to_string(c.plant.default_target_c)), "--target");
        // pid+ff sends the plant's M307 (what a tune gives); pid leaves the default model.
        apply_common(o, c, untuned ? "pid" : "pid+ff");
        parse_fault(fault + "@" + format_fixed(fault_time_s(c.plant, c.target_c, when), 1), c);
        c.seconds = c.fault_at_s + parse_number(o.get("tail", "60"), "--tail");
        c.elf_path = default_elf_path(elf_dir, c.board);
        cases.push_back(BenchCase{c, fault});
      }
  const unsigned jobs = static_cast<unsigned>(parse_number(o.get("jobs", "0"), "--jobs"));
  const auto start = std::chrono::steady_clock::now();
  const std::vector<RunResult> results = run_bench(cases, jobs);
  const bool md = o.has("markdown");
  const char* sep = md ? " | " : "  ";
  std::cout << (md ? "| " : "") << "fault" << sep << "plant" << sep << "board" << sep << "model" << sep << "target"
            << sep << "fault at s" << sep << "Error after s" << sep << "heater off s" << sep << "block peak °C" << sep
            << "lowest °C" << sep << "first Error:" << (md ? " |" : "") << "\n";
  if (md) std::cout << "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const RunConfig& c = cases[i].config;
    const RunResult& r = results[i];
    std::string first = "-";
    std::optional<double> error_s, off_s;
    double peak = 0, low = 0;
    if (r.fault) {
      error_s = r.fault->first_error_s;
      off_s = r.fault->heater_last_on_s;
      peak = r.fault->block_peak_c;
      low = r.fault->sensor_min_before_error_c;
      if (!r.fault->first_error.empty()) first = r.fault->first_error.substr(6, 28);
    }
    if (!r.problems.empty() && !r.fault) first = "problem: " + r.problems.front();
    std::cout << (md ? "| " : "") << cases[i].variant << sep << c.plant.name << sep << c.board.id << sep
              << (untuned ? "default" : "M307 of the plant") << sep << format_fixed(c.target_c, 0) << sep
              << format_fixed(c.fault_at_s, 0) << sep << cell(error_s, 1) << sep << cell(off_s, 1) << sep
              << format_fixed(peak, 1) << sep << format_fixed(low, 1) << sep << first << (md ? " |" : "") << "\n";
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cerr << "bench --faults: " << cases.size() << " runs in " << format_fixed(wall_s, 0) << " s wall\n";
  return 0;
}

}  // namespace sim
