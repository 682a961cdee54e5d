// `hotend-sim bench`: every board × plant with the same settings, run in parallel threads (one
// avr_t per thread), summarised in one table.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "sim/sim_run.h"

namespace sim {

struct BenchCase {
  RunConfig config;
  std::string variant;  // label of the controller/settings variant ("" when there is one)
};

// Runs the cases on `jobs` threads (0: one per hardware thread); results in case order.
// A case that cannot start yields a result whose `problems` says why.
std::vector<RunResult> run_bench(const std::vector<BenchCase>& cases, unsigned jobs);

// One row per case; Markdown (for README) or aligned plain text. The columns after the first
// timed command are headed with `disturbance_name` (e.g. "fan step").
void print_bench_table(std::ostream& out, const std::vector<BenchCase>& cases,
                       const std::vector<RunResult>& results, bool markdown,
                       const std::string& disturbance_name = "dist.");
// What went wrong in which case (host problems, the firmware's Error: lines), one per line, then
// the worst T: report error and the slowest simulation speed.
void print_bench_notes(std::ostream& out, const std::vector<BenchCase>& cases,
                       const std::vector<RunResult>& results);

}  // namespace sim
