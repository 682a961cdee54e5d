// One closed-loop run: a firmware image on a board, a plant, a sensor and a scripted host,
// from power-on through heating to the end, with everything the report and checks need.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sim/avr_board.h"
#include "sim/board_spec.h"
#include "sim/bound.h"
#include "sim/fault_outcome.h"
#include "sim/host_session.h"
#include "sim/metrics.h"
#include "sim/plants.h"

namespace sim {

// PID gains as hosts type them with M301 (Marlin units: output 0–255 per °C, Ki per second,
// Kd in seconds).
struct MarlinGains {
  double kp = 0.0, ki = 0.0, kd = 0.0;
};

// A G-code line sent during setup (no time) or `at_s` seconds after the heating start.
struct TimedCommand {
  std::string line;
  std::optional<double> at_s;
  bool in_tune = false;  // at_s counts from the `ok` to M303 (--autotune), not from M104
};

// `--autotune`: M303 before the heat-up. The run sends `M303 E0 S<target> C<cycles> U1 F<fan>`,
// waits for the tune's end, lets the hotend cool to `cool_to_fraction` of the way from ambient
// to the target (the tuned heat-up then starts nearly cold), and only then sends M104.
struct AutotuneConfig {
  int cycles = 5;
  bool fan = true;
  bool apply = true;
  double cool_to_fraction = 0.02;
  std::optional<double> hot_start_c;  // `M109 S<this>` first: a hot start, as after a print
  double hold_s = 0.0;  // ... then held there this long before M303 (the firmware's steady hold: ≥ 65.5 s)
  std::vector<std::string> after;     // sent when the tune has ended (e.g. another M310 choice)
  // --save-settings FILE: once the tune has ended and `after` was sent, M503's setting lines
  // (the commands, without `echo:` and comments) are written here, for --settings runs to
  // replay; removed at the start, so a failed tune leaves no stale file behind.
  std::string save_settings_path;
};

// What the harness saw of a tune: the firmware's own lines, parsed.
struct TuneOutcome {
  double start_s = 0.0;  // the `ok` to M303, since power-on
  std::optional<double> end_s;  // the finished/failed line
  bool finished = false;
  bool applied = false;
  // Highest true temperature between start and end, counted from the first sample at or below
  // S: a tune started above the target (after printing hotter) first cools, and issue 7's
  // S + 5 °C bounds what the tune itself heats to, not where the hotend was. nullopt: never at
  // or below S (e.g. a tune from above stopped while it cooled).
  std::optional<double> max_true_c;
  std::string result_line;   // "PID Autotune finished! …" or the failure line
  std::string model_line;    // the M307 the tune identified (without the echo: prefix)
  std::string pid_line;      // the M301 it designed
  std::string applied_line;  // what U1 applied ("M310 S1 (state feedback), M307 …")
  // With state feedback applied: M503's M311 lines equal the same design compiled for the host
  // (control/state_feedback_autodesign.h) on the applied M307 — the AVR build computes what
  // the host-tested code computes. nullopt when not checked (no state feedback applied).
  std::optional<bool> board_design_matches_host;
  double a = 0, c = 0, d = 0, f = 0;  // the M307 values
  int cycle_lines = 0;
  double duration_s() const { return end_s ? *end_s - start_s : 0.0; }
};

struct RunConfig {
  BoardSpec board;
  PlantSpec plant;
  std::string elf_path;
  double target_c = 210.0;
  double seconds = 600.0;  // simulated time after the heating start
  double noise_lsb = 0.5;  // Gaussian ADC noise σ, LSB (0: silicon's exact rounding)
  uint64_t seed = 1;
  std::string controller;            // controller_setup.h name, "" when set up by hand
  std::optional<MarlinGains> gains;  // nullopt: sent by nobody (firmware default)
  std::string gains_source;          // how `gains` were chosen, for the report
  std::vector<TimedCommand> gcode;
  FaultKind fault = FaultKind::kNone;
  double fault_at_s = 0.0;  // after the heating start (or after M303's ok: fault_in_tune)
  bool fault_in_tune = false;
  std::string csv_path;
  std::optional<AutotuneConfig> autotune;
  // --settings FILE: setting commands a tune saved (--save-settings), sent before every other
  // set-up command; the run then reads them back with M503 and checks they are the same.
  std::vector<std::string> settings;
  std::string settings_source;  // the file, for the report
  bool silicon_eeprom = false;  // --eeprom-timing silicon: 3.4 ms per EEPROM byte write
  bool print_like = false;  // --print-like: the check is only "nothing tripped" (sim/print_like.h)
};

struct RunResult {
  RunConfig config;
  bool booted = false;
  std::optional<double> heating_start_s;  // t0: the `ok` to M104, since power-on
  double end_s = 0.0;
  CpuState cpu = CpuState::kRunning;
  Metrics metrics;
  PhysicalBound bound;
  int report_count = 0;             // T: reports before any fault
  int report_power_bad = 0;         // of those, with @: missing or outside 0..255
  double report_error_max_c = 0.0;  // see sim_run.cpp: kReportLatencyS
  StepCycleStats step_cycles;
  std::vector<IsrCycleStats> isr_cycles;
  EepromStats eeprom;
  ImageSize image;
  uint32_t stack_max_bytes = 0;   // deepest stack of the run (sim/avr_board.h)
  uint32_t stack_room_bytes = 0;  // RAM above the static data
  double wall_s = 0.0;
  int resets = 0;
  std::vector<std::string> error_lines;  // the firmware's Error: lines
  std::vector<std::string> problems;     // what the harness saw go wrong
  std::vector<std::string> simavr_messages;
  std::vector<ReplyLine> transcript;  // the serial conversation ("> " sent, "< " received)
  std::optional<FaultOutcome> fault;
  std::vector<TraceSample> trace;
  std::optional<TuneOutcome> tune;
  // --settings: M503 after the replay listed exactly the replayed lines (nullopt: not read back).
  std::optional<bool> settings_read_back;

  double sim_speed() const { return wall_s > 0.0 ? end_s / wall_s : 0.0; }
};

// Runs to completion; never throws for firmware misbehaviour (that is in `problems`), throws
// std::runtime_error only if the run cannot start (bad ELF, bad config) or the CSV cannot be
// written.
RunResult run_simulation(const RunConfig& config);

// The board's own figures at the end of a session (run's and serve's): simulated time, control
// step cycles and gaps, EEPROM writes, image size, resets, simavr's messages.
void record_board_figures(const AvrBoard& board, RunResult& r);

}  // namespace sim
