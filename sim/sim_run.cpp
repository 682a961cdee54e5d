#include "sim/sim_run.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <limits>

#include "sim/cli_args.h"
#include "control/state_feedback_autodesign.h"
#include "sim/gcode_format.h"
#include "sim/plant_model.h"
#include "sim/host_session.h"
#include "sim/run_files.h"
#include "sim/sensor.h"

namespace sim {
namespace {

constexpr uint32_t kPlantStepUs = 1000;  // plant and host are serviced every simulated ms
constexpr double kPlantStepS = kPlantStepUs * 1e-6;
// One trace sample per heater PWM period of the firmware (brief: 128 ticks of 1 ms, and the
// plant steps are aligned with the ticks): per-sample means of the true temperature and the
// duty are then free of the PWM ripple a single-lag model shows (±0.3 °C on seed002).
constexpr int kStepsPerTraceSample = 128;
// A T: report may describe the mean over the last control period (128 ms), printed up to one
// more period later: it is compared with the true temperature over this window before it.
constexpr double kReportLatencyS = 0.3;
constexpr double kBootTimeoutS = 5.0;
constexpr double kSetupTimeoutS = 30.0;
constexpr double kTuneTimeoutS = 10800.0;  // M303 (its own limit: 30 min) plus the cool-down (seed000: ~80 min)
constexpr double kM105PeriodS = 5.0;  // M155 reports every second; M105 is polled as well
constexpr double kRunChunkS = 0.25;
// A detached thermistor lying in air: first-order lag towards ambient. EPCOS's glass-bead NTCs
// give ~10-20 s in still air; 15 s (our assumption, not measured).
constexpr double kDetachedLagS = 15.0;

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
  void on_plant_step();
  void on_line(const ReplyLine& line);
  void start_setup();
  void send_heat_up();
  void on_tune_line(const std::string& text, double t_s);
  void send_due_commands(double now_s);
  void inject_fault(double now_s);
  void check_report(const TempReport& report);
  void record_trace(double now_s);
  void finish();
  void evaluate_fault_outcome();
  bool before_fault(double t_s) const {
    return config_.fault == FaultKind::kNone || !fault_abs_s_ || t_s < *fault_abs_s_;
  }

  RunConfig config_;
  RunResult result_;
  AvrBoard board_;
  Plant plant_;
  ThermistorAdc adc_;
  HostSession session_;

  std::vector<TimedCommand> timed_;  // sorted by at_s
  std::vector<TimedCommand> tune_timed_;  // timed from M303's ok (line cleared once sent)
  std::size_t next_timed_ = 0;
  double next_m105_s_ = 0.0;
  double target_sent_c_ = 0.0;
  std::optional<double> fault_abs_s_;
  double detached_c_ = 0.0;  // the detached thermistor's own temperature
  double block_peak_c_ = -1e9;
  std::vector<std::pair<double, double>> true_after_fault_;
  bool plant_fault_active() const { return fault_abs_s_ && is_plant_fault(config_.fault); }
  // What the thermistor sees: the plant's sensor node, or its own temperature once detached.
  double sensed_c() const {
    return plant_fault_active() && config_.fault == FaultKind::kDetached ? detached_c_ : plant_.temperature_c();
  }
  std::optional<double> reset_after_fault_s_;          // first CPU reset after the fault
  uint64_t heater_turn_ons_at_that_reset_ = 0;         // heater().turn_on_count() right after it
  std::deque<std::pair<double, double>> recent_true_;  // (t, true °C) over kReportLatencyS
  // Trace accumulators over one sample period.
  int trace_steps_ = 0;
  double heater_sum_ = 0.0, fan_sum_ = 0.0;
  double true_sum_ = 0.0;
  double true_min_ = std::numeric_limits<double>::infinity();
  double true_max_ = -std::numeric_limits<double>::infinity();
  double code_sum_ = 0.0;
  int code_count_ = 0;
  double reported_c_ = std::numeric_limits<double>::quiet_NaN();
  bool cooling_ = false;  // the tune has ended: waiting for the hotend to cool before M104
  void expect_board_design(const std::string& applied);
  std::vector<std::string> expected_m311_, board_m311_;  // the host's / M503's M311 lines
  bool collecting_m311_ = false;
};

Runner::Runner(const RunConfig& config)
    : config_(config),
      board_(config.board, config.elf_path),
      plant_(config_.plant, kPlantStepS),
      adc_(thermistor::kEpcos100k, config.board.thermistor_pullup_ohm, config.noise_lsb, config.seed),
      session_(board_) {
  result_.config = config;
  for (const TimedCommand& c : config.gcode)
    if (c.at_s) (c.in_tune ? tune_timed_ : timed_).push_back(c);
  std::stable_sort(timed_.begin(), timed_.end(),
                   [](const TimedCommand& a, const TimedCommand& b) { return *a.at_s < *b.at_s; });

  board_.set_adc_source(config.board.hotend_adc_channel, [this] {
    const int code = adc_.sample_code(sensed_c());
    code_sum_ += code;
    ++code_count_;
    return simavr_mv_for_code(code, board_.adc_ref_mv());
  });
  // The bed thermistor sits at ambient, so firmware that watches it sees a sane value.
  const double bed_code = ThermistorAdc(thermistor::kEpcos100k, config.board.thermistor_pullup_ohm, 0.0, 0)
                              .mean_code(config_.plant.ambient_c);
  const uint16_t bed_mv = simavr_mv_for_code(silicon_code(bed_code, 0.0), board_.adc_ref_mv());
  board_.set_adc_source(config.board.bed_adc_channel, [bed_mv] { return bed_mv; });

  board_.every(kPlantStepUs, [this] { on_plant_step(); });
  board_.on_reset([this] {
    if (!fault_abs_s_ || reset_after_fault_s_) return;
    reset_after_fault_s_ = board_.time_s();
    heater_turn_ons_at_that_reset_ = board_.heater().turn_on_count();
  });
  session_.on_line([this](const ReplyLine& line) { on_line(line); });
}

void Runner::on_plant_step() {
  const uint64_t now_cycle = board_.cycle();
  const double now = board_.time_s();
  double heater = board_.heater().take_duty(now_cycle);
  double fan = board_.fan().take_duty(now_cycle);
  if (plant_fault_active()) {
    if (config_.fault == FaultKind::kHeaterDead) heater = 0.0;
    if (config_.fault == FaultKind::kStuckOn) heater = 1.0;
    if (config_.fault == FaultKind::kQuarterPower) heater *= 0.25;
    if (config_.fault == FaultKind::kFanStuck) fan = 1.0;
    if (config_.fault == FaultKind::kDetached)
      detached_c_ += (config_.plant.ambient_c - detached_c_) * (kPlantStepS / kDetachedLagS);
  }
  plant_.step(PlantInput{heater, fan});
  if (fault_abs_s_) block_peak_c_ = std::max(block_peak_c_, plant_.block_temperature_c());

  const double true_c = plant_.temperature_c();
  if (result_.tune && !result_.tune->end_s) result_.tune->max_true_c = std::max(result_.tune->max_true_c, true_c);
  if (cooling_) {
    const double ambient = config_.plant.ambient_c;
    if (true_c <= ambient + config_.autotune->cool_to_fraction * (config_.target_c - ambient)) {
      cooling_ = false;
      send_heat_up();
    }
  }
  recent_true_.emplace_back(now, true_c);
  while (recent_true_.front().first < now - kReportLatencyS) recent_true_.pop_front();

  heater_sum_ += heater;
  fan_sum_ += fan;
  true_sum_ += true_c;
  true_min_ = std::min(true_min_, true_c);
  true_max_ = std::max(true_max_, true_c);
  if (++trace_steps_ == kStepsPerTraceSample) record_trace(now);

  send_due_commands(now);
  session_.poll();
}

void Runner::send_due_commands(double now_s) {
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
  detached_c_ = plant_.temperature_c();
  if (config_.fault == FaultKind::kOpen) adc_.set_fault(SensorFault::kOpen);
  if (config_.fault == FaultKind::kShort) adc_.set_fault(SensorFault::kShorted);
  if (config_.fault == FaultKind::kHang) session_.send("D0");
  if (config_.fault == FaultKind::kM108) session_.send("M108");
  if (config_.fault == FaultKind::kM112) session_.send("M112");
}

void Runner::on_line(const ReplyLine& line) {
  if (collecting_m311_) {
    const std::string prefix = "echo:  M311 I";
    if (line.text.rfind(prefix, 0) == 0) board_m311_.push_back(line.text.substr(7));
    if (line.text == "ok") {  // M503's: its lines are complete
      collecting_m311_ = false;
      result_.tune->board_design_matches_host = board_m311_ == expected_m311_;
    }
  }
  if (line.text == "start" && session_.boot_count() == 1) start_setup();
  if (line.text.rfind("Error:", 0) == 0) result_.error_lines.push_back(line.text);
  if (result_.tune && !cooling_ && !result_.heating_start_s) on_tune_line(line.text, line.t_s);
  // A set-up command this image does not know (e.g. a controller it was built without).
  if (line.text.rfind("echo:Unknown command", 0) == 0) result_.problems.push_back("firmware: " + line.text);
  if (auto report = parse_temp_report(line.text)) {
    reported_c_ = report->temp_c;
    if (before_fault(line.t_s)) check_report(*report);
  }
}

void Runner::start_setup() {
  result_.booted = true;
  if (config_.gains) session_.send(format_gains(*config_.gains));
  for (const TimedCommand& c : config_.gcode)
    if (!c.at_s) session_.send(c.line);
  session_.send("M155 S1");
  if (!config_.autotune) return send_heat_up();
  const AutotuneConfig& a = *config_.autotune;
  if (a.hot_start_c) session_.send("M109 S" + format_decimal(*a.hot_start_c));
  session_.send("M303 E0 S" + format_decimal(config_.target_c) + " C" + std::to_string(a.cycles) +
                    " U" + (a.apply ? "1" : "0") + " F" + (a.fan ? "1" : "0"),
                [this](double t_ok) {
                  result_.tune = TuneOutcome();
                  result_.tune->start_s = t_ok;
                  target_sent_c_ = config_.target_c;
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
    target_sent_c_ = 0.0;  // the firmware switched the heater off
    for (const std::string& command : config_.autotune->after) session_.send(command);
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
  if (!control::design_state_feedback_fopdt(control::HotendModel{q8[0], q8[1], q8[2], q8[3]}, 128, &k)) {
    result_.problems.push_back("the host's build of the board design refuses the applied " + applied.substr(at));
    return;
  }
  expected_m311_ = m311_commands(k);
  expected_m311_.pop_back();  // "M311 W1": the upload's commit, not part of M503
  board_m311_.clear();
  collecting_m311_ = true;
  session_.send("M503");
}

void Runner::send_heat_up() {
  session_.send(format_target(config_.target_c), [this](double t_ok) {
    result_.heating_start_s = t_ok;
    target_sent_c_ = config_.target_c;
    next_m105_s_ = t_ok + kM105PeriodS;
  });
}

void Runner::check_report(const TempReport& report) {
  double lo = recent_true_.front().second, hi = lo;
  for (const auto& sample : recent_true_) {
    lo = std::min(lo, sample.second);
    hi = std::max(hi, sample.second);
  }
  const double error = std::max({0.0, lo - report.temp_c, report.temp_c - hi});
  ++result_.report_count;
  if (report.power < 0 || report.power > 255) ++result_.report_power_bad;
  result_.report_error_max_c = std::max(result_.report_error_max_c, error);
}

void Runner::record_trace(double now_s) {
  TraceSample s;
  s.t_s = now_s;
  s.true_c = true_sum_ / trace_steps_;
  if (fault_abs_s_) true_after_fault_.emplace_back(now_s, s.true_c);
  s.true_ripple_c = true_max_ - true_min_;
  s.sensor_c = code_count_ ? adc_.temperature_for_code(code_sum_ / code_count_)
                           : std::numeric_limits<double>::quiet_NaN();
  s.reported_c = reported_c_;
  s.target_c = target_sent_c_;
  s.heater_duty = heater_sum_ / trace_steps_;
  s.fan_duty = fan_sum_ / trace_steps_;
  result_.trace.push_back(s);
  trace_steps_ = 0;
  heater_sum_ = fan_sum_ = code_sum_ = true_sum_ = 0.0;
  true_min_ = std::numeric_limits<double>::infinity();
  true_max_ = -std::numeric_limits<double>::infinity();
  code_count_ = 0;
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
  result_.end_s = board_.time_s();
  result_.step_cycles = board_.step_cycles();
  result_.image = board_.image_size();
  result_.resets = board_.reset_count();
  result_.simavr_messages = board_.simavr_messages();
  if (board_.simavr_messages_dropped())
    result_.simavr_messages.push_back("(" + std::to_string(board_.simavr_messages_dropped()) + " more)\n");
  for (const std::string& p : session_.problems()) result_.problems.push_back(p);
  result_.transcript = session_.transcript();
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
    record.block_peak_c = block_peak_c_;
    record.true_c = true_after_fault_;
    result_.fault = evaluate_fault(record, session_.lines());
  }
}

}  // namespace

RunResult run_simulation(const RunConfig& config) { return Runner(config).run(); }

}  // namespace sim
