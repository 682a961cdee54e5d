#include "sim/cli.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/bench_command.h"
#include "sim/cli_args.h"
#include "sim/tune_plot.h"
#include "sim/default_gains.h"
#include "sim/print_like.h"
#include "sim/plant_model.h"
#include "sim/report.h"
#include "sim/run_setup.h"
#include "sim/run_files.h"
#include "sim/serve_command.h"
#include "sim/sim_run.h"
#include "sim/svg_plot.h"

namespace sim {
namespace {

constexpr double kFaultRunTailS = 5.0;  // fault runs end this long after the fault by default
constexpr double kPlantFaultTailS = 60.0;  // detached/heater-dead/...: time to detect, then to see the block peak

const char* const kUsage = R"(usage:
  hotend-sim [run] [--board sanguinololu|ramps14] [--plant NAME] [--controller NAME] [--target C]
             [--seconds S] [--csv FILE] [--noise-lsb SIGMA] [--seed N]
             [--gains P,I,D | --gains-rule RULE] [--gcode "CMD;CMD@T"] [--elf FILE]
             [--fault KIND@T] [--max-detect S] [--max-block-above C] [--check] [--max-overshoot C] [--max-steady-error C]
             [--max-report-error C] [--max-steady-p2p C] [--max-recovery S]
             [--max-recovery-ratio R] [--transcript FILE] [--quiet]
             [--autotune [--tune-cycles N] [--tune-fan 0|1] [--tune-from C [--tune-hold S]] [--max-tune-overshoot C]
             [--max-model-error PCT] [--after-tune "CMD;CMD"] [--save-settings FILE]] [--settings FILE]
             [--expect-reply TEXT]...
             [--svg FILE] [--eeprom-timing simavr|silicon] [--max-step-gap-ms MS]
  hotend-sim bench [--markdown] [--autotune] [--boards a,b] [--plants x,y] [--controllers a,b]
             [--variant NAME=GCODE]... [--target C] [--fan-step S] [--seconds S] [--jobs N]
             [--noise-lsb SIGMA] [--seed N] [--gains P,I,D | --gains-rule RULE] [--gcode "CMD@T"]
             [--csv-dir DIR] [--plots DIR] [--elf-dir DIR]
  hotend-sim serve [--board B] [--plant P] [--link PATH] [--speed X] [--fault KIND@T]... [--csv FILE]
             [--elf FILE] [--noise-lsb SIGMA] [--seed N]
  hotend-sim list
  hotend-sim plot --out FILE.svg [--title TEXT] RUN.csv...

run: boots the firmware ELF in simavr on the plant, sends M301 (gains), the controller's set-up
  (--controller: pid, pid+ff, fuzzy, fuzzy+ff, statefb, marlin-zn, paper; M307/M311/M312/M310
  computed from the plant's model, see sim/README.md), the untimed --gcode commands, M155 S1 and
  M104 S<target>; the heating start t0 is the firmware's `ok` to M104 and --seconds counts from
  there. Commands with @T are sent T s after t0; the first one splits the run: quality metrics
  before it, disturbance metrics (max |error|, recovery) after it.
  Defaults: ramps14, hotend40w, no --controller (plain M301, the firmware's default controller),
  the plant's own target/duration, noise σ 0.5 LSB, gains from the plant's FOPDT approximation
  by --gains-rule (simc = SIMC PI with τc = 2τ; also simc-tight, amigo, cohen-coon, zn-step on
  that fit, and zn-relay: M303's relay experiment with classic Ziegler–Nichols; see `list`),
  ELF from this build's firmware directory. --gains/--gains-rule override a controller's gains.
  --print-like (issue 8): M303 at the start, then targets 190–250 °C every 2–5 min and the part
  fan 0–100 % every 30–120 s for --seconds (drawn from --seed); --check wants no Error: line.
  --fault: thermistor open/short or a D0 hang T s after t0; the run ends 5 s after it. Plant
  faults (issue 8): detached (thermistor out of the block, cools in air), heater-dead, stuck-on,
  quarter-power, fan-stuck; the run ends 60 s after it; --check wants `Error:…system stopped!`
  within --max-detect s (10), the block below target + --max-block-above (30) (fan-stuck: no Error).
  --check: exit 1 (listing what failed) unless the run meets the HIL limits: reaches ±1 °C,
  overshoot ≤ 5 °C, |steady mean error| ≤ 0.5 °C, T: reports within 1 °C of the true
  temperature and with @: in 0..255, heater duty in 0–100 %, no Error: or unknown-command line,
  no reset, back in ±1 °C after a timed command (all adjustable; --max-steady-p2p adds an
  oscillation limit, --max-recovery a recovery time, --max-recovery-ratio the same in multiples
  of the physical bound); fault runs: heater off within 1 s and the Error: line, or for a hang
  reset + start + off.
  --transcript: the serial conversation with simulated times ("> " sent, "< " received).
  --autotune: the user story of issue 7 — `M303 E0 S<target> C<cycles> U1 F<0|1>` first (the
  board identifies the hotend and designs its controllers), then a cool-down to 2 % of the way
  from ambient to the target, then M104 and the timed commands as usual. The report adds the
  tune's duration, its maximum above S (once at or below S) and the identified model; --check adds: the tune finished
  and applied, never more than --max-tune-overshoot (5 °C) above S. --tune-from C: a hot start
  (M109 S<C> before M303), --tune-hold S: held there S s first (≥ 66 s: the board then takes the
  hotend's gain from the hold, control/steady_hold.h); --after-tune: G-code sent when the tune has ended (e.g. "M310 S2 F1":
  another controller on the tuned settings); --save-settings FILE: then M503's setting lines
  (M307 … M301, as commands) to FILE. --settings FILE (no --autotune): those lines first, on a
  fresh board, read back with M503 (--check: the same), then the run as usual — a tune's
  settings on a cold hotend without its tune. --expect-reply TEXT (repeatable): --check fails
  unless the firmware sent a line containing TEXT. Timed commands and faults may count from M303's ok: "M108@tune+90",
  --fault open@tune+60 (kinds also m108, m112: the host stops the tune). Serial-layer kinds
  (sim/serial_scenario.h): m112-wait, m112-burst (heater off within 1 s of the M112's last
  byte), overrun, overrun-numbered (the lost input reported, nothing glued).
  --eeprom-timing silicon: an EEPROM byte write takes 3.4 ms as on the ATmega1284P/2560 (EEPE
  stays set, accesses meanwhile are ignored; simavr's default completes it at once); the report
  counts the writes. --max-step-gap-ms: --check fails if two control steps start further apart.
  --svg FILE: temperature and duty against time; with --autotune from M303 on, with the response
  of the model the tune identified (simulated on the same duties) laid over the hotend's.
bench: every controller × board × plant (or the given ones) in parallel, heating to each
  plant's default target, a part-fan step 0 → 100 % at --fan-step s (default: the plant's
  default duration; 0 = none) and --seconds in all (default: fan step + half the default
  duration); prints one table and under it every problem or Error: line. --variant NAME=GCODE
  replaces the controllers by hand-made set-ups (the grid again per variant, with its G-code).
  --csv-dir writes each run's trace; --plots DIR (needs --csv-dir) one SVG per plant with every
  controller on the first board. --autotune (or "autotune" in --controllers): M303 U1 first, then
  the tuned controller's heat-up and fan step, beside pid+ff from the plant's own model and
  marlin-zn (Marlin's M303); adds the tune's duration, maximum above S and the model found.
  --faults (issue 8): fault × plant × board detection table instead: each fault (--fault-kinds,
  default detached,heater-dead,stuck-on,quarter-power) at the target (--fault-at hold) or halfway
  through the heat-up (--fault-at half), with the plant's M307 set (--untuned: the default model),
  --tail s after the fault (60): Error after, heater off, block peak, lowest sensor-node reading.
serve: a virtual printer. Boots the firmware on the plant and exposes UART0 as a pseudo-terminal
  (printed; --link makes a symlink to it) for pronsole, Pronterface or OctoPrint at 115200 baud.
  Real time unless --speed X (X × real time: the host's timing stretches with it). Host bytes
  reach the UART at the line rate the firmware programmed (what the host writes ahead waits in
  the kernel's pty buffer; a full RX ring loses bytes, as on silicon). --fault KIND@T (as run's,
  repeatable) T s after the host's first M104/M109/M303 with S > 0. Ends on SIGINT/SIGTERM
  with the session's report (the last set-point's control quality, Error: lines); --csv FILE
  writes the trace.
plot: temperature and heater duty of several --csv runs against time in one SVG.
)";

int run_command(const std::vector<std::string>& args) {
  const Options o = parse_options(args, {"check", "quiet", "autotune", "print-like"});
  reject_unknown(o, {"board", "plant", "controller", "target", "seconds", "csv", "noise-lsb", "seed", "gains",
                     "gains-rule", "gcode", "elf", "fault", "max-detect", "max-block-above", "transcript", "max-overshoot", "max-steady-error",
                     "max-report-error", "max-steady-p2p", "max-recovery", "max-recovery-ratio",
                     "tune-cycles", "tune-fan", "tune-from", "tune-hold", "after-tune", "max-tune-overshoot", "max-model-error",
                     "svg", "expect-reply", "eeprom-timing", "max-step-gap-ms", "save-settings", "settings"});
  RunConfig c;
  c.board = board_named(o.get("board", "ramps14"));
  c.plant = plant_named(o.get("plant", "hotend40w"));
  c.target_c = parse_number(o.get("target", std::to_string(c.plant.default_target_c)), "--target");
  if (o.has("fault")) parse_fault(o.get("fault"), c);
  const double default_seconds =
      c.fault == FaultKind::kNone
          ? c.plant.default_seconds
          : (c.fault_in_tune ? 0.0 : c.fault_at_s) + (is_plant_fault(c.fault) ? kPlantFaultTailS : kFaultRunTailS);
  c.seconds = parse_number(o.get("seconds", std::to_string(default_seconds)), "--seconds");
  c.csv_path = o.get("csv");
  c.elf_path = o.has("elf") ? o.get("elf") : default_elf_path(HOTEND_SIM_FIRMWARE_DIR, c.board);
  apply_common(o, c, o.get("controller"));
  const std::string eeprom_timing = o.get("eeprom-timing", "simavr");
  if (eeprom_timing != "simavr" && eeprom_timing != "silicon")
    throw std::invalid_argument("--eeprom-timing: simavr or silicon");
  c.silicon_eeprom = eeprom_timing == "silicon";
  if (o.has("print-like")) {  // M303 first (unless a controller is given), then a print's targets and fan
    c.print_like = true;
    for (const TimedCommand& t : print_like_gcode(c.seconds, c.seed)) c.gcode.push_back(t);
  }
  if (o.has("autotune") || (o.has("print-like") && !o.has("controller"))) {
    if (o.has("controller")) throw std::invalid_argument("--autotune sets the controller itself (M303 U1)");
    AutotuneConfig a;
    a.cycles = static_cast<int>(parse_number(o.get("tune-cycles", "5"), "--tune-cycles"));
    a.fan = parse_number(o.get("tune-fan", "1"), "--tune-fan") != 0;
    if (o.has("tune-from")) a.hot_start_c = parse_number(o.get("tune-from"), "--tune-from");
    if (o.has("tune-hold")) a.hold_s = parse_number(o.get("tune-hold"), "--tune-hold");
    for (const TimedCommand& t : parse_gcode(o.get("after-tune"))) a.after.push_back(t.line);
    a.save_settings_path = o.get("save-settings");
    if (c.print_like) a.cool_to_fraction = 1.0;  // the print starts when the tune ends
    c.autotune = a;
    if (!o.has("gains")) {  // the tune designs them
      c.gains.reset();
      c.gains_source.clear();
    }
  }

  if (o.has("save-settings") && !c.autotune) throw std::invalid_argument("--save-settings saves a tune's settings: add --autotune");
  if (o.has("settings")) {
    if (c.autotune || o.has("controller"))
      throw std::invalid_argument("--settings set the controller themselves: not with --autotune, --print-like's tune or --controller");
    if (o.has("gains-rule")) throw std::invalid_argument("--settings hold their M301: --gains-rule does not apply (--gains overrides it)");
    c.settings = read_lines(o.get("settings"));
    c.settings_source = o.get("settings");
    if (!o.has("gains")) {  // the settings hold M301
      c.gains.reset();
      c.gains_source.clear();
    }
  }

  CheckLimits limits;
  limits.max_overshoot_c = parse_number(o.get("max-overshoot", "5"), "--max-overshoot");
  limits.max_steady_error_c = parse_number(o.get("max-steady-error", "0.5"), "--max-steady-error");
  limits.max_report_error_c = parse_number(o.get("max-report-error", "1"), "--max-report-error");
  if (o.has("max-steady-p2p"))
    limits.max_steady_peak_to_peak_c = parse_number(o.get("max-steady-p2p"), "--max-steady-p2p");
  if (o.has("max-recovery")) limits.max_recovery_s = parse_number(o.get("max-recovery"), "--max-recovery");
  if (o.has("max-recovery-ratio"))
    limits.max_recovery_bound_ratio = parse_number(o.get("max-recovery-ratio"), "--max-recovery-ratio");
  limits.max_detect_s = parse_number(o.get("max-detect", "10"), "--max-detect");
  limits.max_block_above_c = parse_number(o.get("max-block-above", "30"), "--max-block-above");
  limits.max_tune_overshoot_c = parse_number(o.get("max-tune-overshoot", "5"), "--max-tune-overshoot");
  limits.expected_replies = o.all("expect-reply");
  if (o.has("max-step-gap-ms")) limits.max_step_gap_ms = parse_number(o.get("max-step-gap-ms"), "--max-step-gap-ms");
  if (o.has("max-model-error"))
    limits.max_model_error = parse_number(o.get("max-model-error"), "--max-model-error") / 100.0;

  const RunResult result = run_simulation(c);
  if (!o.has("quiet")) print_report(std::cout, result);
  if (o.has("transcript")) write_transcript(o.get("transcript"), result.transcript);
  if (o.has("svg")) {
    std::vector<PlotSeries> series = tune_plot_series(result);
    const std::string title = c.plant.name + " on " + c.board.id +
                              (series.empty() ? std::string(": the run") : ": M303, then the tuned heat-up and a fan step");
    if (series.empty()) {  // no tune: the run's own trace
      PlotSeries s{c.controller.empty() ? "firmware" : c.controller, {}, {}, {}, {}};
      for (const TraceSample& t : result.trace) {
        s.time_s.push_back(t.t_s);
        s.true_c.push_back(t.true_c);
        s.target_c.push_back(t.target_c);
        s.heater_duty.push_back(t.heater_duty);
      }
      series.push_back(s);
    }
    write_svg_plot(o.get("svg"), title, series);
  }
  if (!o.has("check")) return 0;
  const std::vector<std::string> failed = failed_checks(result, limits);
  for (const std::string& f : failed) std::cout << "CHECK FAILED: " << f << "\n";
  if (failed.empty()) std::cout << "CHECK PASSED\n";
  return failed.empty() ? 0 : 1;
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
              << "      100 % settles " << format_fixed(design::dc_gain(p.model), 1) << " K above ambient ("
              << format_fixed(design::dc_gain(p.model, 1.0), 1) << " with the fan); default "
              << format_fixed(p.default_target_c, 0) << " °C for " << format_fixed(p.default_seconds, 0)
              << " s, physical bound " << format_fixed(b.settling_s, 1) << " s\n"
              << "      default gains P " << format_fixed(g.gains.kp, 3) << " I "
              << format_fixed(g.gains.ki, 4) << " D " << format_fixed(g.gains.kd, 2) << " (" << g.description
              << ")\n";
    const HotendModelSetting m = hotend_model_for(p);
    std::cout << "      feedforward model " << m307_command(m) << " (" << m.source << ")\n";
    try {
      std::cout << "      state feedback: " << state_feedback_for(p).description << "\n";
    } catch (const std::exception& e) {
      std::cout << "      state feedback: " << e.what() << "\n";
    }
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
    if (command == "serve") return serve_command(args);
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
