#include "sim/report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "sim/plant_model.h"

namespace sim {
namespace {

void print_fault(std::ostream& out, const RunResult& r) {
  const FaultOutcome& f = *r.fault;
  out << "fault              " << fault_name(r.config.fault) << " at " << format_fixed(r.config.fault_at_s, 1)
      << (r.config.fault_in_tune ? " s into M303\n" : " s after heating start\n")
      << "  heater last on   " << format_optional(f.heater_last_on_s, 3) << " s after the fault"
      << (f.heater_on_at_end ? " (STILL ON at the end)" : "") << "\n";
  if (!f.expected_error.empty())
    out << "  Error:" << f.expected_error << "  "
        << (f.error_line_s ? "printed after " + format_fixed(*f.error_line_s, 3) + " s" : "NOT printed")
        << "\n";
  for (const std::string& p : f.serial_problems) out << "  serial           " << p << "\n";
  if (is_plant_fault(r.config.fault))
    out << "  first Error:     " << (f.first_error_s ? format_fixed(*f.first_error_s, 3) + " s: " + f.first_error : "none")
        << "\n"
        << "  block peak       " << format_fixed(f.block_peak_c, 1) << " °C after the fault\n"
        << "  sensor-node min  " << format_fixed(f.sensor_min_before_error_c, 1) << " °C until the Error (true)\n";
  if (r.config.fault == FaultKind::kHang)
    out << "  watchdog reset   " << (f.reset_s ? format_fixed(*f.reset_s, 3) + " s after D0" : "NONE") << "\n"
        << "  start again      " << (f.restarted ? "yes" : "NO") << "\n"
        << "  heater after it  " << (f.heater_on_after_reset ? "ON at some point" : "off") << "\n";
}

// Largest interval between control-step starts, ms of simulated time.
double step_gap_ms(const RunResult& r) {
  return 1000.0 * double(r.step_cycles.max_gap_cycles) / double(r.config.board.cpu_hz);
}

// One line: max / mean cycles of each handler that ran (simavr counts no entry cycles).
void print_isr_cycles(std::ostream& out, const RunResult& r) {
  std::string line;
  for (const IsrCycleStats& s : r.isr_cycles) {
    if (s.count == 0) continue;
    line += (line.empty() ? "" : ", ") + s.name + " " + std::to_string(s.max_cycles) + " / " +
            format_fixed(s.mean_cycles(), 0);
  }
  if (!line.empty()) out << "interrupts         " << line << " cycles max / mean (+4–5 entry on silicon)\n";
}

}  // namespace

std::string format_fixed(double value, int decimals) {
  if (std::isnan(value)) return "-";
  char text[32];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return text;
}

std::string format_optional(const std::optional<double>& value, int decimals) {
  return value ? format_fixed(*value, decimals) : "-";
}

void print_report(std::ostream& out, const RunResult& r) {
  const RunConfig& c = r.config;
  const Metrics& m = r.metrics;
  out << "board              " << c.board.name << " (" << c.board.id << ", " << c.board.mcu << ")\n"
      << "firmware           " << c.elf_path << "\n"
      << "image              flash " << r.image.flash_bytes << " B, RAM " << r.image.ram_bytes << " B, stack max "
      << r.stack_max_bytes << " B of " << r.stack_room_bytes << " B free\n"
      << "plant              " << c.plant.name << ": " << c.plant.description << "\n"
      << "target             " << format_fixed(c.target_c, 1) << " °C for " << format_fixed(c.seconds, 0)
      << " s, ADC noise σ " << format_fixed(c.noise_lsb, 2) << " LSB\n"
      << (c.controller.empty() ? "" : "controller         " + c.controller + "\n")
      << "gains              "
      << (c.gains ? "P " + format_fixed(c.gains->kp, 3) + " I " + format_fixed(c.gains->ki, 4) + " D " +
                        format_fixed(c.gains->kd, 2)
                  : std::string(c.settings.empty() ? "firmware default" : "the settings' M301"))
      << (c.gains_source.empty() ? "" : "  (" + c.gains_source + ")") << "\n";
  if (!c.settings.empty())
    out << "settings           " << c.settings.size() << " lines from " << c.settings_source << ", M503 "
        << (!r.settings_read_back ? std::string("never read them back")
                                  : *r.settings_read_back ? std::string("read them back the same")
                                                          : std::string("read them back DIFFERENT"))
        << "\n";
  if (r.tune) {
    const TuneOutcome& t = *r.tune;
    out << "autotune (M303)    " << (t.end_s ? format_fixed(t.duration_s(), 1) + " s, " : std::string("did not end, "))
        << t.cycle_lines << " relay cycles, "
        << (t.max_true_c ? "max " + format_fixed(*t.max_true_c - c.target_c, 2) + " °C above S; " : std::string("never at or below S; "))
        << (t.result_line.empty() ? std::string("no result line") : t.result_line) << "\n";
    if (!t.model_line.empty()) out << "  identified       " << t.model_line << "\n";
    if (!t.pid_line.empty()) out << "  designed         " << t.pid_line << "\n";
    if (t.applied) out << "  applied (U1)     " << t.applied_line << "\n";
    if (t.board_design_matches_host)
      out << "  board's M311     " << (*t.board_design_matches_host ? "equal to" : "DIFFERENT from")
          << " the same design built for the host\n";
  }
  if (r.heating_start_s) {
    out << "heating start      " << format_fixed(*r.heating_start_s, 3) << " s after power-on\n"
        << "time to reach      " << format_optional(m.time_to_reach_s, 1) << " s (first inside ±1 °C)\n"
        << "overshoot          " << format_fixed(m.overshoot_c, 2) << " °C\n"
        << "settling (±1 °C)   " << format_optional(m.settling_s, 1) << " s\n";
    if (r.bound.reachable)
      out << "physical bound     " << format_fixed(r.bound.settling_s, 1) << " s (100 % until "
          << format_fixed(r.bound.switch_s, 1) << " s, then " << format_fixed(100.0 * r.bound.steady_duty, 1)
          << " %); ratio " << (m.settling_s ? format_fixed(*m.settling_s / r.bound.settling_s, 2) : "-")
          << "\n";
    else
      out << "physical bound     target unreachable at 100 % heater power\n";
    out << "steady state       " << format_fixed(m.steady_from_s, 0) << "–" << format_fixed(m.steady_to_s, 0)
        << " s: mean error " << format_fixed(m.steady_mean_error_c, 3) << " °C, peak-to-peak "
        << format_fixed(m.steady_peak_to_peak_c, 3) << " °C (PWM ripple within a period "
        << format_fixed(m.steady_ripple_c, 3) << " °C)\n"
        << "IAE                " << format_fixed(m.iae_c_s, 1) << " °C·s\n";
    if (m.disturbance)
      out << "after " << format_fixed(m.disturbance->at_s, 0) << " s        max |error| "
          << format_fixed(m.disturbance->max_deviation_c, 2) << " °C, recovery "
          << format_optional(m.disturbance->recovery_s, 1) << " s\n";
  }
  out << "T: reports         " << r.report_count << ", max |reported − true| "
      << format_fixed(r.report_error_max_c, 3) << " °C\n"
      << "control step       " << r.step_cycles.count << " steps, max " << r.step_cycles.max_cycles
      << " cycles, mean " << format_fixed(r.step_cycles.mean_cycles(), 0) << ", largest gap "
      << format_fixed(step_gap_ms(r), 1) << " ms\n";
  print_isr_cycles(out, r);
  out
      << "simulated          " << format_fixed(r.end_s, 1) << " s in " << format_fixed(r.wall_s, 2)
      << " s wall (" << format_fixed(r.sim_speed(), 0) << "× real time)\n";
  if (r.config.silicon_eeprom)
    out << "EEPROM (silicon)   " << r.eeprom.writes << " byte writes of 3.4 ms, " << r.eeprom.ignored_while_busy
        << " accesses while busy (ignored)\n";
  if (r.fault) print_fault(out, r);
  for (const std::string& line : r.error_lines) out << "firmware said      " << line << "\n";
  for (const std::string& p : r.problems) out << "problem            " << p << "\n";
  for (const std::string& msg : r.simavr_messages) out << "simavr             " << msg;
}

std::vector<std::string> failed_checks(const RunResult& r, const CheckLimits& limits) {
  std::vector<std::string> failed;
  auto require = [&failed](bool ok, const std::string& what) {
    if (!ok) failed.push_back(what);
  };
  require(r.booted, "the firmware never printed `start`");
  if (r.config.autotune && r.config.fault_in_tune) {
    // A fault during M303: the tune ends in Marlin's failure wording, then the usual fault checks.
    require(r.tune && r.tune->result_line.rfind("PID Autotune failed!", 0) == 0,
            "no `PID Autotune failed!` line after the fault during M303");
  } else if (r.config.autotune) {
    require(r.tune && r.tune->finished, "M303 did not finish" + (r.tune ? ": " + r.tune->result_line : std::string()));
    if (r.tune && r.tune->end_s) {
      require(r.tune->max_true_c.has_value(), "M303 ended without the hotend ever at or below S");
      if (r.tune->max_true_c)
        require(*r.tune->max_true_c <= r.config.target_c + limits.max_tune_overshoot_c,
                "M303 reached " + format_fixed(*r.tune->max_true_c - r.config.target_c, 2) + " °C above S > " +
                    format_fixed(limits.max_tune_overshoot_c, 2));
    }
    if (r.config.autotune->apply) require(r.tune && r.tune->applied, "M303 U1 did not apply its result");
    if (r.tune && r.tune->board_design_matches_host)
      require(*r.tune->board_design_matches_host,
              "the board's state-feedback constants (M503) differ from the same design built for the host");
    const HotendModelSetting truth = hotend_model_for(r.config.plant);
    if (limits.max_model_error && r.tune && r.tune->finished && truth.source == "exact FOPDT") {
      const double e = *limits.max_model_error;
      auto within = [&](const char* what, double got, double want, double limit) {
        require(std::fabs(got - want) <= limit * want, std::string("tuned ") + what + " " + format_fixed(got, 2) +
                                                            " vs the plant's " + format_fixed(want, 2) + ": more than " +
                                                            format_fixed(100.0 * limit, 0) + " % off");
      };
      within("A (gain)", r.tune->a, truth.rise_k, e);
      within("C (time constant)", r.tune->c, truth.time_constant_s, e);
      within("D (dead time)", r.tune->d, truth.dead_time_s, e);
      within("F (fan loss)", r.tune->f, truth.fan_loss_pct, 2.0 * e);
    }
  }
  if (!r.config.settings.empty())
    require(r.settings_read_back.value_or(false),
            "the settings from " + r.config.settings_source + " did not read back the same (M503)");
  if (limits.max_step_gap_ms)
    require(step_gap_ms(r) <= *limits.max_step_gap_ms, "largest gap between control steps " +
                                                           format_fixed(step_gap_ms(r), 1) + " ms > " +
                                                           format_fixed(*limits.max_step_gap_ms, 1));
  for (const std::string& want : limits.expected_replies) {
    bool seen = false;
    for (const ReplyLine& line : r.transcript)
      seen = seen || (line.text.rfind("< ", 0) == 0 && line.text.find(want) != std::string::npos);
    require(seen, "the firmware never replied \"" + want + "\"");
  }
  if (!r.config.fault_in_tune) require(r.heating_start_s.has_value(), "the firmware never acknowledged M104");
  require(r.cpu == CpuState::kRunning, "the simulated CPU stopped or crashed");
  if (!r.heating_start_s && !r.config.fault_in_tune) return failed;

  if (r.config.print_like) {  // changing targets and fan: no false trip is what counts
    require(r.problems.empty(), "the host saw problems (see report)");
    require(r.error_lines.empty(), "the firmware printed an Error: line");
    require(r.resets == 0, "the CPU was reset during the run");
    require(r.report_count > 0, "no T: reports");
    return failed;
  }
  if (r.config.fault == FaultKind::kNone) {
    const Metrics& m = r.metrics;
    require(r.problems.empty(), "the host saw problems (see report)");
    require(r.error_lines.empty(), "the firmware printed an Error: line");
    require(r.resets == 0, "the CPU was reset during the run");
    require(m.time_to_reach_s.has_value(), "never reached ±1 °C of the target");
    require(m.overshoot_c <= limits.max_overshoot_c, "overshoot " + format_fixed(m.overshoot_c, 2) +
                                                         " °C > " + format_fixed(limits.max_overshoot_c, 2));
    require(std::fabs(m.steady_mean_error_c) <= limits.max_steady_error_c,
            "steady-state mean error " + format_fixed(m.steady_mean_error_c, 3) + " °C, limit ±" +
                format_fixed(limits.max_steady_error_c, 2));
    if (limits.max_steady_peak_to_peak_c)
      require(m.steady_peak_to_peak_c <= *limits.max_steady_peak_to_peak_c,
              "steady-state peak-to-peak " + format_fixed(m.steady_peak_to_peak_c, 3) + " °C > " +
                  format_fixed(*limits.max_steady_peak_to_peak_c, 3));
    if (m.disturbance) {
      require(m.disturbance->recovery_s.has_value(), "not back within ±1 °C after the disturbance at " +
                                                         format_fixed(m.disturbance->at_s, 0) + " s");
      std::optional<double> limit_s = limits.max_recovery_s;
      if (limits.max_recovery_bound_ratio && r.bound.reachable) {
        const double by_bound = *limits.max_recovery_bound_ratio * r.bound.settling_s;
        limit_s = limit_s ? std::min(*limit_s, by_bound) : by_bound;
      }
      if (limit_s && m.disturbance->recovery_s)
        require(*m.disturbance->recovery_s <= *limit_s, "recovery " + format_fixed(*m.disturbance->recovery_s, 1) +
                                                            " s after the disturbance > " +
                                                            format_fixed(*limit_s, 1) + " s");
    }
    // Duty within 0–100 %: what the firmware reports (@: 0..255) and what the pin did.
    require(r.report_power_bad == 0,
            std::to_string(r.report_power_bad) + " T: reports with @: missing or outside 0..255");
    for (const TraceSample& s : r.trace)
      if (!(s.heater_duty >= 0.0 && s.heater_duty <= 1.0)) {
        failed.push_back("heater duty " + format_fixed(100.0 * s.heater_duty, 1) + " % outside 0–100 %");
        break;
      }
    require(r.report_count > 0, "no T: reports");
    require(r.report_error_max_c <= limits.max_report_error_c,
            "reported temperature off by " + format_fixed(r.report_error_max_c, 3) + " °C > " +
                format_fixed(limits.max_report_error_c, 2));
    return failed;
  }
  require(r.fault.has_value(), "the fault was never injected");
  if (!r.fault) return failed;
  const FaultOutcome& f = *r.fault;
  if (r.config.fault == FaultKind::kOverrun || r.config.fault == FaultKind::kOverrunNumbered) {
    for (const std::string& p : f.serial_problems) failed.push_back(p);
    require(r.resets == 0, "the CPU was reset during the run");
    return failed;
  }
  if (r.config.fault == FaultKind::kFanStuck) {  // the controller compensates: no trip
    require(r.error_lines.empty(), "the firmware printed an Error: line with the fan stuck at 100 %");
    return failed;
  }
  require(!f.heater_on_at_end, "the heater is on at the end of the run");
  if (is_plant_fault(r.config.fault)) {
    const double target = r.config.target_c;
    // Quarter power must be reported before the hotend falls 15 °C (below), not within a time.
    const double detect_limit_s = r.config.fault == FaultKind::kQuarterPower ? r.config.seconds : limits.max_detect_s;
    require(f.error_line_s && *f.error_line_s <= detect_limit_s,
            "no `Error:..system stopped!` within " + format_fixed(detect_limit_s, 1) + " s of the fault (" +
                format_optional(f.error_line_s, 3) + " s)");
    if (f.error_line_s)
      require(f.heater_last_on_s && *f.heater_last_on_s <= *f.error_line_s + limits.max_heater_off_s,
              "heater still on " + format_optional(f.heater_last_on_s, 3) + " s after the fault");
    if (r.config.fault != FaultKind::kStuckOn)  // stuck on heats whatever the firmware does
      require(f.block_peak_c <= target + limits.max_block_above_c,
              "block reached " + format_fixed(f.block_peak_c, 1) + " °C > target + " +
                  format_fixed(limits.max_block_above_c, 0));
    if (r.config.fault == FaultKind::kQuarterPower)
      require(f.sensor_min_before_error_c >= target - 15.0,
              "fell to " + format_fixed(f.sensor_min_before_error_c, 1) + " °C before the Error");
    require(r.resets == 0, "the CPU was reset during the run");
    return failed;
  }
  if (r.config.fault == FaultKind::kHang) {
    require(f.reset_s.has_value(), "no watchdog reset after D0");
    require(f.restarted, "no `start` after the watchdog reset");
    require(!f.heater_on_after_reset, "the heater came on after the watchdog reset");
  } else {
    require(f.heater_last_on_s && *f.heater_last_on_s <= limits.max_heater_off_s,
            "heater still on " + format_optional(f.heater_last_on_s, 3) + " s after the fault");
    if (!f.expected_error.empty())  // M108 stops quietly: only its `ok`
      require(f.error_line_s.has_value(), "no `Error:" + f.expected_error + "` line");
    require(r.resets == 0, "the CPU was reset during the run");
  }
  return failed;
}

}  // namespace sim
