#include "sim/bench.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <functional>
#include <thread>

#include "sim/plant_model.h"
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

struct Column {
  std::string title;
  std::function<std::string(const BenchCase&, const RunResult&)> cell;
};

// "-" for runs that never started heating.
std::string when_heated(const RunResult& r, std::string text) {
  return r.heating_start_s ? text : std::string("-");
}

std::vector<Column> columns(bool variants, bool disturbance, bool tune, const std::string& dist) {
  std::vector<Column> cols;
  if (variants) cols.push_back({"controller", [](const BenchCase& c, const RunResult&) { return c.variant; }});
  cols.push_back({"board", [](const BenchCase& c, const RunResult&) { return c.config.board.id; }});
  cols.push_back({"plant", [](const BenchCase& c, const RunResult&) { return c.config.plant.name; }});
  cols.push_back(
      {"target °C", [](const BenchCase& c, const RunResult&) { return format_fixed(c.config.target_c, 0); }});
  cols.push_back({"reach s", [](const BenchCase&, const RunResult& r) {
                    return when_heated(r, format_optional(r.metrics.time_to_reach_s, 1));
                  }});
  cols.push_back({"overshoot °C", [](const BenchCase&, const RunResult& r) {
                    return when_heated(r, format_fixed(r.metrics.overshoot_c, 2));
                  }});
  cols.push_back({"settling s", [](const BenchCase&, const RunResult& r) {
                    return when_heated(r, format_optional(r.metrics.settling_s, 1));
                  }});
  cols.push_back({"bound s", [](const BenchCase&, const RunResult& r) {
                    return r.bound.reachable ? format_fixed(r.bound.settling_s, 1) : "-";
                  }});
  cols.push_back({"ratio", [](const BenchCase&, const RunResult& r) {
                    const auto& s = r.metrics.settling_s;
                    return s && r.bound.reachable ? format_fixed(*s / r.bound.settling_s, 2) : "-";
                  }});
  cols.push_back({"ss err °C", [](const BenchCase&, const RunResult& r) {
                    return when_heated(r, format_fixed(r.metrics.steady_mean_error_c, 3));
                  }});
  cols.push_back({"ss p-p °C", [](const BenchCase&, const RunResult& r) {
                    return when_heated(r, format_fixed(r.metrics.steady_peak_to_peak_c, 3));
                  }});
  cols.push_back({"IAE °C·s", [](const BenchCase&, const RunResult& r) {
                    return when_heated(r, format_fixed(r.metrics.iae_c_s, 0));
                  }});
  if (tune) {
    cols.push_back({"tune s", [](const BenchCase&, const RunResult& r) {
                      return r.tune && r.tune->finished ? format_fixed(r.tune->duration_s(), 0) : std::string("-");
                    }});
    cols.push_back({"tune max − S °C", [](const BenchCase&, const RunResult& r) {
                      return r.tune && r.tune->max_true_c ? format_fixed(*r.tune->max_true_c - r.config.target_c, 2) : std::string("-");
                    }});
    cols.push_back({"model: tuned / true (A C D F)", [](const BenchCase&, const RunResult& r) {
                      if (!r.tune) return std::string("-");
                      const HotendModelSetting t = hotend_model_for(r.config.plant);
                      return (r.tune->finished ? format_fixed(r.tune->a, 0) + " " + format_fixed(r.tune->c, 1) + " " +
                                                     format_fixed(r.tune->d, 1) + " " + format_fixed(r.tune->f, 1)
                                               : std::string("failed")) +
                             " / " + format_fixed(t.rise_k, 0) + " " + format_fixed(t.time_constant_s, 1) + " " +
                             format_fixed(t.dead_time_s, 1) + " " + format_fixed(t.fan_loss_pct, 1);
                    }});
  }
  if (disturbance) {
    cols.push_back({dist + " max |err| °C", [](const BenchCase&, const RunResult& r) {
                      const auto& d = r.metrics.disturbance;
                      return d ? format_fixed(d->max_deviation_c, 2) : "-";
                    }});
    cols.push_back({dist + " recovery s", [](const BenchCase&, const RunResult& r) {
                      const auto& d = r.metrics.disturbance;
                      return d ? format_optional(d->recovery_s, 1) : "-";
                    }});
  }
  cols.push_back({"step cycles max / mean", [](const BenchCase&, const RunResult& r) {
                    return std::to_string(r.step_cycles.max_cycles) + " / " +
                           format_fixed(r.step_cycles.mean_cycles(), 0);
                  }});
  cols.push_back({"flash / RAM B", [](const BenchCase&, const RunResult& r) {
                    return std::to_string(r.image.flash_bytes) + " / " + std::to_string(r.image.ram_bytes);
                  }});
  cols.push_back({"notes", [](const BenchCase&, const RunResult& r) {
                    return r.problems.empty() && r.error_lines.empty() ? std::string() : "see below";
                  }});
  return cols;
}

// Display width in characters (UTF-8 continuation bytes do not count).
std::size_t width(const std::string& s) {
  return static_cast<std::size_t>(
      std::count_if(s.begin(), s.end(), [](char ch) { return (ch & 0xC0) != 0x80; }));
}

std::string case_name(const BenchCase& c) {
  return (c.variant.empty() ? "" : c.variant + "/") + c.config.board.id + "/" + c.config.plant.name;
}

}  // namespace

std::vector<RunResult> run_bench(const std::vector<BenchCase>& cases, unsigned jobs) {
  if (jobs == 0) jobs = std::max(1u, std::thread::hardware_concurrency());
  std::vector<RunResult> results(cases.size());
  // Longest simulated runs first, so the last ones to finish are short and every core stays
  // busy to the end (the seed000 runs last six times longer than the others).
  std::vector<std::size_t> order(cases.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&cases](std::size_t a, std::size_t b) {
    return cases[a].config.seconds > cases[b].config.seconds;
  });
  std::atomic<std::size_t> next{0};
  // Each thread owns the avr_t of the case it runs; simavr keeps no shared mutable state
  // across instances apart from the logger, which AvrBoard installs once.
  auto worker = [&] {
    for (std::size_t k = next++; k < cases.size(); k = next++) results[order[k]] = run_case(cases[order[k]]);
  };
  std::vector<std::thread> threads;
  for (unsigned t = 0; t < std::min<std::size_t>(jobs, cases.size()); ++t) threads.emplace_back(worker);
  for (std::thread& t : threads) t.join();
  return results;
}

void print_bench_table(std::ostream& out, const std::vector<BenchCase>& cases,
                       const std::vector<RunResult>& results, bool markdown, const std::string& disturbance_name) {
  const bool variants =
      std::any_of(cases.begin(), cases.end(), [](const BenchCase& c) { return !c.variant.empty(); });
  const bool disturbance = std::any_of(results.begin(), results.end(),
                                       [](const RunResult& r) { return r.metrics.disturbance.has_value(); });
  const bool tune = std::any_of(results.begin(), results.end(), [](const RunResult& r) { return r.tune.has_value(); });
  const std::vector<Column> cols = columns(variants, disturbance, tune, disturbance_name);

  std::vector<std::vector<std::string>> rows(1);
  for (const Column& c : cols) rows[0].push_back(c.title);
  for (std::size_t i = 0; i < results.size(); ++i) {
    rows.emplace_back();
    for (const Column& c : cols) rows.back().push_back(c.cell(cases[i], results[i]));
  }
  if (markdown)  // a '|' inside a cell ("max |err|") would split it into two columns
    for (auto& row : rows)
      for (std::string& cell : row)
        for (std::size_t at = cell.find('|'); at != std::string::npos; at = cell.find('|', at + 2))
          cell.replace(at, 1, "\\|");
  std::vector<std::size_t> widths(cols.size(), 0);
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

void print_bench_notes(std::ostream& out, const std::vector<BenchCase>& cases,
                       const std::vector<RunResult>& results) {
  for (std::size_t i = 0; i < results.size(); ++i) {
    for (const std::string& line : results[i].error_lines)
      out << case_name(cases[i]) << ": firmware: " << line << "\n";
    for (const std::string& p : results[i].problems) out << case_name(cases[i]) << ": " << p << "\n";
  }
  // The issue-2 figures that are the same for every controller, as one line instead of columns.
  double worst_report = 0.0, slowest = 0.0;
  for (const RunResult& r : results) {
    // After a firmware fault (e.g. MAXTEMP) the true temperature may leave the thermistor
    // table, where the reading clamps by design: only fault-free runs count.
    if (r.error_lines.empty()) worst_report = std::max(worst_report, r.report_error_max_c);
    if (r.sim_speed() > 0.0 && (slowest == 0.0 || r.sim_speed() < slowest)) slowest = r.sim_speed();
  }
  out << "\nlargest |T: report − true| (runs without Error: lines) " << format_fixed(worst_report, 2)
      << " °C; slowest simulation "
      << format_fixed(slowest, 0) << "× real time\n";
}

}  // namespace sim
