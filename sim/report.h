// The human-readable report of one run, and the pass/fail checks the HIL tests use.
#pragma once

#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "sim/sim_run.h"

namespace sim {

// Pass limits for `--check`; defaults are issue 2's HIL acceptance criteria.
struct CheckLimits {
  double max_overshoot_c = 5.0;
  double max_steady_error_c = 0.5;  // |steady-state mean error|
  double max_report_error_c = 1.0;  // T: reports vs the true sensor temperature
  double max_heater_off_s = 1.0;    // fault runs: heater off this soon after the fault
  // Plant faults (issue 8): the Error line this soon after the fault, the block never hotter
  // than the target + this.
  double max_detect_s = 10.0;
  double max_block_above_c = 30.0;
  // Sustained oscillation (issue 3): steady-state peak-to-peak; off unless given.
  std::optional<double> max_steady_peak_to_peak_c;
  // Recovery after the first timed command (e.g. a part-fan step): back in ±1 °C and staying
  // there within this many seconds (without it: merely back by the end of the run).
  std::optional<double> max_recovery_s;
  // The same as a multiple of the plant's physical bound (issue 3's HIL tests: 2 × bound).
  std::optional<double> max_recovery_bound_ratio;
  // --autotune runs: the tune must finish (and apply, with U1) without the true temperature
  // ever passing S + this (issue 7).
  double max_tune_overshoot_c = 5.0;
  // On plants that are exactly FOPDT: the tuned M307 A, C, D within this fraction of the
  // plant's, F within twice it (issue 7: 10 % and 20 %). Off unless given.
  std::optional<double> max_model_error;
  // Replies the firmware must have sent (a received line containing each text), e.g. the M310
  // report after M502 + M501 that shows the stored controller came back.
  std::vector<std::string> expected_replies;
  // The largest interval between two control-step starts (nominally 128 ms); off unless given.
  std::optional<double> max_step_gap_ms;
};

void print_report(std::ostream& out, const RunResult& result);
// Every failed check, as one line each; empty means pass.
std::vector<std::string> failed_checks(const RunResult& result, const CheckLimits& limits);

// Shared number formatting for reports and tables: "-" for an absent value.
std::string format_fixed(double value, int decimals);
std::string format_optional(const std::optional<double>& value, int decimals);

}  // namespace sim
