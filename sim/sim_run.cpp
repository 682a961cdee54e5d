#include "sim/sim_run.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "sim/cli_args.h"
#include "control/state_feedback_autodesign.h"
#include "sim/gcode_format.h"
#include "sim/plant_model.h"
#include "sim/host_session.h"
#include "sim/run_files.h"
#include "sim/fault_injection.h"
#include "sim/hotend_rig.h"
#include "sim/serial_scenario.h"

namespace sim {
namespace {

constexpr double kBootTimeoutS = 5.0;
constexpr double kSetupTimeoutS = 30.0;
constexpr double kTuneTimeoutS = 10800.0;  // M303 (its own limit: 30 min) plus the cool-down (seed000: ~80 min)
constexpr double kM105PeriodS = 5.0;  // M155 reports every second; M105 is polled as well
constexpr double kRunChunkS = 0.25;

std::string format_gains(const MarlinGains& g) {
  return "M301 P" + format_decimal(g.kp) + " I" + format_decimal(g.ki) + " D" + format_decimal(g.kd);
}

std::string format_target(double target_c) { return "M104 S" + format_decimal(target_c); }

// A, C, D, F of the "M307 A… C… D… F…" at the start of `text` (letters absent stay 0).
std::array<double, 4> m307_values(const std::string& text) {
  std::array<double, 4> v{0, 0, 0, 0};
  const std::string letters = "ACDF";
  for (const std::string& word : split(text, ' ')) {
    const std::size_t i = word.size() < 2 ? std::string::npos : letters.find(word[0]);
    if (i != std::string::npos) v[i] = std::atof(word.c_str() + 1);
  }
  return v;
}

class Runner {
 public:
  explicit Runner(const RunConfig& config);
  RunResult run();

 private:
  void on_plant_step(double now_s, double true_c);
  void on_line(const ReplyLine& line);
  void start_setup();
  void send_tune();  // M303 with the run's target and options
  void send_heat_up();
  void on_tune_line(const std::string& text, double t_s);
  void send_due_commands(double now_s);
  void inject_fault(double now_s);
  void check_report(const TempReport& report);
  void finish();
  void evaluate_fault_outcome();
  bool before_fault(double t_s) const {
    return config_.fault == FaultKind::kNone || !fault_abs_s_ || t_s < *fault_abs_s_;
  }

  RunConfig config_;
  RunResult result_;
  HotendRig rig_;
  AvrBoard& board_;
  HostSession session_;
  SerialScenario serial_;

  std::vector<TimedCommand> timed_;  // sorted by at_s
  std::vector<TimedCommand> tune_timed_;  // timed from M303's ok (line cleared once sent)
  std::size_t next_timed_ = 0;
  double next_m105_s_ = 0.0;
  std::optional<double> fault_abs_s_;
  std::optional<double> reset_after_fault_s_;          // first CPU reset after the fault
  uint64_t heater_turn_ons_at_that_reset_ = 0;         // heater().turn_on_count() right after it
  bool cooling_ = false;  // the tune has ended: waiting for the hotend to cool before M104
  std::optional<double> tune_send_s_;  // --tune-hold: when the hold is over and M303 goes out
  void expect_board_design(const std::string& applied);
  // Sends M503 and hands `done` its setting lines as commands (settings_command).
  void capture_settings(std::function<void(const std::vector<std::string>&)> done);
  void save_settings(const std::vector<std::string>& lines);
  std::vector<std::string> m503_lines_;
  bool capturing_m503_ = false;
};

// "echo:  M307 A… ; comment" (an M503 setting line) → "M307 A…"; "" for M503's other lines.
std::string settings_command(const std::string& text) {
  const std::string prefix = "echo:  M";
  if (text.rfind(prefix, 0) != 0) return std::string();
  std::string command = text.substr(prefix.size() - 1);
  const std::size_t comment = command.find(';');
  if (comment != std::string::npos) command.erase(comment);
  while (!command.empty() && command.back() == ' ') command.pop_back();
  return command;
}

Runner::Runner(const RunConfig& config)
    : config_(config),
      rig_(config.board, config.plant, config.elf_path, config.noise_lsb, config.seed),
      board_(rig_.board()),
      session_(board_),
      serial_(session_, config.fault) {
  result_.config = config;
  if (config.silicon_eeprom) board_.use_silicon_eeprom_timing();
  if (config.autotune && !config.autotune->save_settings_path.empty())
    std::remove(config.autotune->save_settings_path.c_str());
  for (const TimedCommand& c : config.gcode)
    if (c.at_s) (c.in_tune ? tune_timed_ : timed_).push_back(c);
  std::stable_sort(timed_.begin(), timed_.end(),
                   [](const TimedCommand& a, const TimedCommand& b) { return *a.at_s < *b.at_s; });

  rig_.on_step([this](double now_s, double true_c) { on_plant_step(now_s, true_c); });
  board_.on_reset([this] {
    if (!fault_abs_s_ || reset_after_fault_s_) return;
    reset_after_fault_s_ = board_.time_s();
    heater_turn_ons_at_that_reset_ = board_.heater().turn_on_count();
  });
  session_.on_line([this](const ReplyLine& line) { on_line(line); });
}

void Runner::on_plant_step(double now, double true_c) {
  if (result_.tune && !result_.tune->end_s) {
    std::optional<double>& max_c = result_.tune->max_true_c;
    if (max_c || true_c <= config_.target_c) max_c = std::max(max_c.value_or(true_c), true_c);
  }
  if (cooling_) {
    const double ambient = config_.plant.ambient_c;
    if (true_c <= ambient + config_.autotune->cool_to_fraction * (config_.target_c - ambient)) {
      cooling_ = false;
      send_heat_up();
    }
  }
  send_due_commands(now);
  serial_.poll(now);
  session_.poll();
}

void Runner::send_due_commands(double now_s) {
  if (tune_send_s_ && now_s >= *tune_send_s_) {
    tune_send_s_.reset();
    send_tune();
  }
  if (result_.tune) {  // commands and faults timed from the tune's start
    const double t = now_s - result_.tune->start_s;
    for (TimedCommand& c : tune_timed_)
      if (!c.line.empty() && t >= *c.at_s) {
        session_.send(c.line);
        c.line.clear();
      }
    if (config_.fault_in_tune && !fault_abs_s_ && t >= config_.fault_at_s) inject_fault(now_s);
  }
  if (!result_.heating_start_s) return;
  const double t = now_s - *result_.heating_start_s;
  while (next_timed_ < timed_.size() && t >= *timed_[next_timed_].at_s)
    session_.send(timed_[next_timed_++].line);
  if (config_.fault != FaultKind::kNone && !config_.fault_in_tune && !fault_abs_s_ && t >= config_.fault_at_s)
    inject_fault(now_s);
  if (before_fault(now_s) && now_s >= next_m105_s_ && session_.idle()) {
    session_.send("M105");
    next_m105_s_ = now_s + kM105PeriodS;
  }
}

void Runner::inject_fault(double now_s) {
  fault_abs_s_ = now_s;
  sim::inject_fault(config_.fault, rig_, [this](const std::string& line) { session_.send(line); });
  if (is_serial_scenario(config_.fault)) serial_.start(config_.target_c);
}

void Runner::on_line(const ReplyLine& line) {
  if (capturing_m503_) {
    const std::string command = settings_command(line.text);
    if (!command.empty()) m503_lines_.push_back(command);
  }
  if (line.text == "start" && session_.boot_count() == 1) start_setup();
  if (line.text.rfind("Error:", 0) == 0) result_.error_lines.push_back(line.text);
  if (result_.tune && !cooling_ && !result_.heating_start_s) on_tune_line(line.text, line.t_s);
  // A set-up command this image does not know (e.g. a controller it was built without).
  if (line.text.rfind("echo:Unknown command", 0) == 0) result_.problems.push_back("firmware: " + line.text);
  if (auto report = parse_temp_report(line.text)) {
    rig_.set_reported(report->temp_c);
    if (before_fault(line.t_s)) check_report(*report);
  }
}

void Runner::capture_settings(std::function<void(const std::vector<std::string>&)> done) {
  // M503's lines follow its last byte (the firmware answers a complete line) and end at its ok;
  // the host sends nothing in between, and T: auto-reports are no setting lines.
  session_.send(
      "M503", [this, done](double) {
        capturing_m503_ = false;
        done(m503_lines_);
      },
      [this](double) {
        m503_lines_.clear();
        capturing_m503_ = true;
      });
}

void Runner::save_settings(const std::vector<std::string>& lines) {
  const std::string& path = config_.autotune->save_settings_path;
  if (!result_.tune || !result_.tune->finished || !result_.tune->applied) {
    result_.problems.push_back("--save-settings: nothing saved, the tune did not finish and apply");
    return;
  }
  if (lines.empty()) {
    result_.problems.push_back("--save-settings: M503 listed no settings");
    return;
  }
  if (!write_lines(path, lines)) result_.problems.push_back("--save-settings: cannot write " + path);
}

void Runner::start_setup() {
  result_.booted = true;
  for (const std::string& command : config_.settings) session_.send(command);
  if (!config_.settings.empty())
    capture_settings([this](const std::vector<std::string>& lines) { result_.settings_read_back = lines == config_.settings; });
  if (config_.gains) session_.send(format_gains(*config_.gains));
  for (const TimedCommand& c : config_.gcode)
    if (!c.at_s) session_.send(c.line);
  session_.send("M155 S1");
  if (!config_.autotune) return send_heat_up();
  const AutotuneConfig& a = *config_.autotune;
  if (a.hot_start_c && a.hold_s > 0) {
    // Held at the start temperature (as a printer idling there) before M303: send_due_commands.
    session_.send("M109 S" + format_decimal(*a.hot_start_c), [this, &a](double t_ok) { tune_send_s_ = t_ok + a.hold_s; });
    return;
  }
  if (a.hot_start_c) session_.send("M109 S" + format_decimal(*a.hot_start_c));
  send_tune();
}

void Runner::send_tune() {
  const AutotuneConfig& a = *config_.autotune;
  session_.send("M303 E0 S" + format_decimal(config_.target_c) + " C" + std::to_string(a.cycles) +
                    " U" + (a.apply ? "1" : "0") + " F" + (a.fan ? "1" : "0"),
                [this](double t_ok) {
                  result_.tune = TuneOutcome();
                  result_.tune->start_s = t_ok;
                  rig_.set_target(config_.target_c);
                });
}

// The tune's lines (firmware/controller_autotune.cpp): the end is the line after the result.
void Runner::on_tune_line(const std::string& text, double t_s) {
  TuneOutcome& tune = *result_.tune;
  auto starts = [&text](const char* prefix) { return text.rfind(prefix, 0) == 0; };
  if (starts(" bias:")) ++tune.cycle_lines;
  if (starts("PID Autotune finished!")) tune.finished = true;
  if (starts("PID Autotune finished!") || starts("PID Autotune failed!")) {
    tune.result_line = text;
    tune.end_s = t_s;
  }
  const std::size_t m307 = text.find("M307 ");
  if (starts("echo:Autotune model") && m307 != std::string::npos) {
    tune.model_line = text.substr(m307);
    const std::array<double, 4> v = m307_values(tune.model_line);
    tune.a = v[0], tune.c = v[1], tune.d = v[2], tune.f = v[3];
  }
  const std::size_t m301 = text.find("M301 ");
  if (starts("echo:Autotune PID") && m301 != std::string::npos) tune.pid_line = text.substr(m301);
  if (starts("echo:Autotune applied")) {
    tune.applied = true;
    const std::size_t m310 = text.find("M310 ");
    if (m310 != std::string::npos) tune.applied_line = text.substr(m310);
    if (tune.applied_line.rfind("M310 S1", 0) == 0) expect_board_design(tune.applied_line);
  }
  // The last line of every ending: applied / not applied, or the failure itself.
  if (starts("echo:Autotune applied") || starts("echo:Autotune not applied") || starts("PID Autotune failed!") ||
      (tune.end_s && starts("Error:"))) {
    cooling_ = true;
    rig_.set_target(0.0);  // the firmware switched the heater off
    for (const std::string& command : config_.autotune->after) session_.send(command);
    if (!config_.autotune->save_settings_path.empty())
      capture_settings([this](const std::vector<std::string>& lines) { save_settings(lines); });
  }
}

// The M307 in the applied line reads back as the exact Q8 values (firmware/controller_commands:
// two or three decimals), so the host can run the board's design on the same numbers.
void Runner::expect_board_design(const std::string& applied) {
  const std::size_t at = applied.find("M307 ");
  if (at == std::string::npos) return;
  int32_t q8[4];
  const std::array<double, 4> v = m307_values(applied.substr(at));
  for (int i = 0; i < 4; ++i) q8[i] = static_cast<int32_t>(std::lround(v[i] * 256.0));
  control::StateFeedbackConstants k;
  const bool paced = applied.find("paced by D") != std::string::npos;  // T_cl ≥ D (control/autotune_design.h)
  // "two lags <τ1> s and <τ2> s, pace <κ>": the two-lag law on those (T_cl ≥ κ·τ2), with M307's A and F.
  const std::size_t lags = applied.find("two lags ");
  const bool two_lags = lags != std::string::npos;
  unsigned pace_units = 0, pace_tenths = 0;
  control::HotendModel model{q8[0], q8[1], q8[2], q8[3]};
  if (two_lags) {
    double c = 0, d = 0;
    if (std::sscanf(applied.c_str() + lags, "two lags %lf s and %lf s, pace %u.%1u", &c, &d, &pace_units, &pace_tenths) != 4) {
      result_.problems.push_back("the applied line's two lags do not read: " + applied);
      return;
    }
    model.time_constant_q8 = static_cast<int32_t>(std::lround(c * 256.0));
    model.dead_time_q8 = static_cast<int32_t>(std::lround(d * 256.0));
  }
  if (!(two_lags ? control::design_state_feedback_two_lags(model, 128, &k, static_cast<uint8_t>(10 * pace_units + pace_tenths))
                 : control::design_state_feedback_fopdt(model, 128, &k, paced))) {
    result_.problems.push_back("the host's build of the board design refuses the applied " + applied.substr(at));
    return;
  }
  std::vector<std::string> expected = m311_commands(k);
  expected.pop_back();  // "M311 W1": the upload's commit (M503 lists it too; compared: the I lines)
  capture_settings([this, expected](const std::vector<std::string>& lines) {
    std::vector<std::string> board;
    for (const std::string& line : lines)
      if (line.rfind("M311 I", 0) == 0) board.push_back(line);
    result_.tune->board_design_matches_host = board == expected;
  });
}

void Runner::send_heat_up() {
  session_.send(format_target(config_.target_c), [this](double t_ok) {
    result_.heating_start_s = t_ok;
    rig_.set_target(config_.target_c);
    next_m105_s_ = t_ok + kM105PeriodS;
  });
}

void Runner::check_report(const TempReport& report) {
  const double error = rig_.report_error_c(report);
  ++result_.report_count;
  if (report.power < 0 || report.power > 255) ++result_.report_power_bad;
  result_.report_error_max_c = std::max(result_.report_error_max_c, error);
}

RunResult Runner::run() {
  const auto wall_start = std::chrono::steady_clock::now();
  for (;;) {
    const double now = board_.time_s();
    double until = now + kRunChunkS;
    if (result_.heating_start_s) until = std::min(until, *result_.heating_start_s + config_.seconds);
    result_.cpu = board_.run_until(board_.cycles_from_s(until));
    const double t = board_.time_s();
    if (result_.cpu != CpuState::kRunning) {
      result_.problems.push_back(result_.cpu == CpuState::kCrashed ? "the CPU crashed" : "the CPU stopped");
      break;
    }
    if (!result_.booted && t > kBootTimeoutS) {
      result_.problems.push_back("no `start` line within 5 s of power-on");
      break;
    }
    const bool tuning = config_.autotune && (!result_.tune || !result_.tune->end_s || cooling_);
    if (tuning && t > kTuneTimeoutS) {
      result_.problems.push_back("M303 and the cool-down took longer than " + format_decimal(kTuneTimeoutS) + " s");
      break;
    }
    if (!tuning && !result_.heating_start_s && t > (config_.autotune ? kTuneTimeoutS : kSetupTimeoutS)) {
      result_.problems.push_back("no `ok` to M104 within 30 s of power-on");
      break;
    }
    if (result_.heating_start_s && t >= *result_.heating_start_s + config_.seconds) break;
    if (config_.fault_in_tune && fault_abs_s_ && t >= *fault_abs_s_ + config_.seconds) break;
  }
  result_.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  finish();
  return std::move(result_);
}

void Runner::finish() {
  record_board_figures(board_, result_);
  for (const std::string& p : session_.problems()) result_.problems.push_back(p);
  result_.transcript = session_.transcript();
  result_.trace = rig_.trace();
  result_.bound = physical_bound(config_.plant, config_.target_c);
  if (config_.fault_in_tune) return evaluate_fault_outcome();
  if (!result_.heating_start_s) return;

  const double t0 = *result_.heating_start_s;
  std::optional<double> split_s;
  if (!timed_.empty()) split_s = *timed_.front().at_s;
  if (config_.fault != FaultKind::kNone) split_s = config_.fault_at_s;
  result_.metrics = compute_metrics(result_.trace, t0, config_.target_c, split_s);

  evaluate_fault_outcome();
  if (!config_.csv_path.empty()) write_trace_csv(config_.csv_path, result_.trace);
}

void Runner::evaluate_fault_outcome() {
  if (config_.fault != FaultKind::kNone && fault_abs_s_) {
    const PinMeter& heater = board_.heater();
    FaultRecord record;
    record.kind = config_.fault;
    record.fault_s = *fault_abs_s_;
    record.heater_on_at_end = heater.is_on();
    record.heater_last_change_s = double(heater.last_change_cycle()) / board_.frequency_hz();
    record.reset_s = reset_after_fault_s_;
    record.heater_turned_on_after_reset = heater.turn_on_count() > heater_turn_ons_at_that_reset_;
    // Serial scenarios: timed from the last byte of the M112/M108 the host sent.
    if (is_serial_scenario(config_.fault)) record.fault_s = serial_.urgent_sent_s().value_or(record.fault_s);
    record.block_peak_c = rig_.block_peak_c();
    record.true_c = rig_.true_after_fault();
    result_.fault = evaluate_fault(record, session_.lines());
    if (config_.fault == FaultKind::kOverrun || config_.fault == FaultKind::kOverrunNumbered)
      result_.fault->serial_problems = check_overrun_replies(config_.fault, session_.lines(), *fault_abs_s_);
  }
}

}  // namespace

void record_board_figures(const AvrBoard& board, RunResult& r) {
  r.end_s = board.time_s();
  r.step_cycles = board.step_cycles();
  r.isr_cycles = board.isr_cycles();
  r.eeprom = board.eeprom_stats();
  r.image = board.image_size();
  r.stack_max_bytes = board.stack_max_bytes();
  r.stack_room_bytes = board.stack_room_bytes();
  r.resets = board.reset_count();
  r.simavr_messages = board.simavr_messages();
  if (board.simavr_messages_dropped())
    r.simavr_messages.push_back("(" + std::to_string(board.simavr_messages_dropped()) + " more)\n");
}

RunResult run_simulation(const RunConfig& config) { return Runner(config).run(); }

}  // namespace sim
