#include "sim/bench.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <thread>

#include "sim/report.h"

namespace sim {
namespace {

RunResult run_case(const BenchCase& c) {
  try {
    return run_simulation(c.config);
  } catch (const std::exception& e) {
    RunResult failed;
    failed.config = c.config;
    failed.problems.push_back(e.what());
    return failed;
  }
}

std::vector<std::string> row_for(const RunResult& r) {
  const Metrics& m = r.metrics;
  const bool ran = r.heating_start_s.has_value();
  auto when_ran = [ran](std::string text) { return ran ? text : std::string("-"); };
  std::string ratio = "-";
  if (m.settling_s && r.bound.reachable) ratio = format_fixed(*m.settling_s / r.bound.settling_s, 2);
  return {r.config.board.id,
          r.config.plant.name,
          format_fixed(r.config.target_c, 0),
          when_ran(format_optional(m.time_to_reach_s, 1)),
          when_ran(format_fixed(m.overshoot_c, 2)),
          when_ran(format_optional(m.settling_s, 1)),
          r.bound.reachable ? format_fixed(r.bound.settling_s, 1) : "-",
          ratio,
          when_ran(format_fixed(m.steady_mean_error_c, 3)),
          when_ran(format_fixed(m.steady_peak_to_peak_c, 3)),
          when_ran(format_fixed(m.iae_c_s, 0)),
          std::to_string(r.step_cycles.max_cycles) + " / " + format_fixed(r.step_cycles.mean_cycles(), 0),
          format_fixed(r.sim_speed(), 0),
          std::to_string(r.image.flash_bytes) + " / " + std::to_string(r.image.ram_bytes),
          r.problems.empty() && r.error_lines.empty() ? "" : "see report"};
}

const std::vector<std::string> kHeader = {
    "board", "plant", "target °C", "reach s", "overshoot °C", "settling s", "bound s", "ratio",
    "ss mean err °C", "ss p-p °C", "IAE °C·s", "step cycles max / mean", "sim speed ×",
    "flash / RAM B", "notes"};

// Display width in characters (UTF-8 continuation bytes do not count).
std::size_t width(const std::string& s) {
  return static_cast<std::size_t>(std::count_if(s.begin(), s.end(), [](char ch) { return (ch & 0xC0) != 0x80; }));
}

}  // namespace

std::vector<RunResult> run_bench(const std::vector<BenchCase>& cases, unsigned jobs) {
  if (jobs == 0) jobs = std::max(1u, std::thread::hardware_concurrency());
  std::vector<RunResult> results(cases.size());
  std::atomic<std::size_t> next{0};
  auto worker = [&] {
    for (std::size_t i = next++; i < cases.size(); i = next++) results[i] = run_case(cases[i]);
  };
  std::vector<std::thread> threads;
  for (unsigned t = 0; t < std::min<std::size_t>(jobs, cases.size()); ++t) threads.emplace_back(worker);
  for (std::thread& t : threads) t.join();
  return results;
}

void print_bench_table(std::ostream& out, const std::vector<RunResult>& results, bool markdown) {
  std::vector<std::vector<std::string>> rows{kHeader};
  for (const RunResult& r : results) rows.push_back(row_for(r));
  std::vector<std::size_t> widths(kHeader.size(), 0);
  for (const auto& row : rows)
    for (std::size_t i = 0; i < row.size(); ++i) widths[i] = std::max(widths[i], width(row[i]));
  for (std::size_t r = 0; r < rows.size(); ++r) {
    for (std::size_t i = 0; i < rows[r].size(); ++i) {
      const std::string& cell = rows[r][i];
      out << (markdown ? "| " : (i ? "  " : "")) << cell << std::string(widths[i] - width(cell), ' ')
          << (markdown ? " " : "");
    }
    out << (markdown ? "|\n" : "\n");
    if (markdown && r == 0) {
      for (std::size_t w : widths) out << "|" << std::string(w + 2, '-');
      out << "|\n";
    }
  }
}

}  // namespace sim
