#include "firmware/controller_autotune.h"

#include "control/state_feedback_autodesign.h"
#include "firmware/controller_commands.h"

namespace firmware {
namespace {

constexpr int32_t kDefaultTargetQ8 = 210L * 256;  // Marlin's M303 default is the hotend's 150;
                                                  // issue 7 asks for a printing temperature
constexpr int32_t kDefaultCycles = 5;

// "echo:Autotune ", which starts this firmware's own report lines (one copy in flash).
const gcode::FlashText* echo_autotune_text() { return GCODE_TEXT("echo:Autotune "); }

// Marlin's failure prefix, one copy in flash for the two reports that start with it.
const gcode::FlashText* failed_text() { return GCODE_TEXT("PID Autotune failed! "); }

// The three gains after their labels: " Kp: 1.00 Ki: …" (Marlin's line) or " P1.00 I…" (M301).
// (Labels as separate arguments: GCODE_TEXT in an array initializer crashes avr-gcc 5.4's LTO.)
void write_gains(gcode::Output& out, const gcode::FlashText* p, const gcode::FlashText* i, const gcode::FlashText* d,
                 const control::PidGains& g) {
  const gcode::FlashText* const labels[3] = {p, i, d};
  const int32_t values[3] = {g.kp_q16, g.ki_q16, g.kd_q16};
  for (uint8_t k = 0; k < 3; ++k) {
    out.print(labels[k]);
    out.write_q16(values[k]);
  }
}

void write_gain_line(gcode::Output& out, const gcode::FlashText* name, int32_t value_q16) {
  out.print(GCODE_TEXT("#define DEFAULT_"));
  out.print(name);
  out.write_char(' ');
  out.write_q16(value_q16);
  out.end_line();
}

// Marlin's closing lines, which host plugins parse, then this firmware's own: the model, the
// gains as commands. noinline (as write_sf_summary): inside write_result, whose frame holds the
// design's scratch (432 B), every local sat beyond AVR's 63-byte LDD/STD reach.
__attribute__((noinline)) void write_design(gcode::Output& out, const control::AutotuneResult& r,
                                            const control::TunedDesign& d) {
  write_gains(out, GCODE_TEXT(" Kp: "), GCODE_TEXT(" Ki: "), GCODE_TEXT(" Kd: "), d.pid);
  out.print(GCODE_TEXT("\nPID Autotune finished! Put the last Kp, Ki and Kd constants from below into "
                       "Configuration.h\n"));
  write_gain_line(out, GCODE_TEXT("Kp"), d.pid.kp_q16);
  write_gain_line(out, GCODE_TEXT("Ki"), d.pid.ki_q16);
  write_gain_line(out, GCODE_TEXT("Kd"), d.pid.kd_q16);
  out.print(echo_autotune_text());
  out.print(!r.hot_start  ? GCODE_TEXT("model (cold start: heat-up, ")
            : r.held_gain ? GCODE_TEXT("model (hot start: the gain of the hold before M303, cool-down, ")
                          : GCODE_TEXT("model (hot start: cool-down, "));
  // No relay cycle (Tu 0): a dead-time hotend's settled approach held the target instead.
  out.print(r.ultimate.tu_q8 == 0 ? GCODE_TEXT("hold at the target") : GCODE_TEXT("relay"));
  out.print(r.model.fan_loss_pct_q8 != 0 ? GCODE_TEXT(", part fan): ") : GCODE_TEXT("): "));
  write_m307(out, r.model);
  // An unsure tune's two-lag fit (control/lag_fit.h): the applied M307 is their two-point FOPDT.
  if (r.second_lag_q8 > 0) {
    out.print(echo_autotune_text());
    out.print(GCODE_TEXT("two lags fitted to the whole record: "));
    out.write_exact(r.first_lag_q8, 8);
    out.print(GCODE_TEXT(" s and "));
    out.write_exact(r.second_lag_q8, 8);
    out.print(GCODE_TEXT(" s\n"));
  }
  // The reading noise the tune measured (σ, °C): above 0.3 °C a thermistor or its wiring is
  // noisy enough to cost the model accuracy (docs/autotune.md, "Noisy sensors").
  if (r.noise_q8 != control::AutotuneResult::kNoiseUnmeasured) {
    out.print(echo_autotune_text());
    out.print(GCODE_TEXT("reading noise "));
    out.write_q8(r.noise_q8);
    out.print(r.noise_q8 > control::Autotune::kNoisyQ8 ? GCODE_TEXT(" C (sigma): noisy, check the thermistor and its wiring\n")
                                                       : GCODE_TEXT(" C (sigma)\n"));
  }
  out.print(echo_autotune_text());
  out.print(GCODE_TEXT("PID (SIMC PI on that model, dead time "));
  out.write_q8(d.model.dead_time_q8);
  out.print(GCODE_TEXT(" s): M301"));
  write_gains(out, GCODE_TEXT(" P"), GCODE_TEXT(" I"), GCODE_TEXT(" D"), d.pid);
  out.end_line();
}

// The controller M303 picks: `rest` completes "M310 S1 (state feedback" (its variants share
// that text) or, without state feedback, is the whole M310 S0 text. The two-lag law names its
// lags exactly and its pace κ (T_cl ≥ κ·τ2; hotend-sim's check of the board's M311 designs from
// them and M307's A and F).
void write_choice(gcode::Output& out, bool state_feedback, const gcode::FlashText* rest, const control::TunedDesign& d) {
  if (state_feedback) out.print(GCODE_TEXT("M310 S1 (state feedback"));
  if (state_feedback && d.two_lags) {
    out.print(GCODE_TEXT(", two lags "));
    out.write_exact(d.sf_c_q8, 8);
    out.print(GCODE_TEXT(" s and "));
    out.write_exact(d.sf_d_q8, 8);
    out.print(GCODE_TEXT(" s, pace "));
    out.write_uint(d.lag_pace_tenths / 10u);
    out.write_char('.');
    out.write_uint(d.lag_pace_tenths % 10u);
  }
  out.print(rest);
}

// The board's state-feedback design in one line (nullptr: it failed); for the two-lag law its
// lags (the applied M307's C and D, or after an unsure tune's fit τ1 and τ2).
__attribute__((noinline)) void write_sf_summary(gcode::Output& out, const control::StateFeedbackConstants* sf,
                                                const control::TunedDesign& d) {
  if (sf == nullptr) {
    out.print(echo_autotune_text());
    out.print(GCODE_TEXT("state feedback: this model is outside what the board designs\n"));
    return;
  }
  out.print(echo_autotune_text());
  out.print(GCODE_TEXT("state feedback designed: "));
  if (d.two_lags) {
    out.print(GCODE_TEXT("two lags "));
    out.write_q8(d.sf_c_q8);
    out.print(GCODE_TEXT(" s and "));
    out.write_q8(d.sf_d_q8);
    out.print(GCODE_TEXT(" s (no dead time), "));
  }
  out.print(GCODE_TEXT("law every "));
  out.write_uint(sf->decimation);
  out.print(GCODE_TEXT(" x 128 ms, predictor over "));
  out.write_uint(sf->delay);
  out.print(GCODE_TEXT(" law periods (M503 lists its M311 lines once applied)\n"));
}

}  // namespace

bool AutotuneJob::begin(const gcode::Command& cmd, gcode::Output& out, const gcode::FlashText* refusal,
                        uint8_t fan_duty, int32_t hold_gain_q8) {
  if (!cmd.valid(out)) return false;
  int32_t heater = 0, target_q8 = kDefaultTargetQ8, cycles = kDefaultCycles, use = 0, fan = 1;
  if (!cmd.integer('E', -1, 0x7FFF, &heater, out)) return false;
  if (heater == -1) {
    out.error_line(GCODE_TEXT("PID Autotune failed! E-1: this firmware has no bed heater loop (hotend E0 only)"));
    return false;
  }
  if (heater != 0) {
    out.error_line(GCODE_TEXT("PID Autotune failed! Bad extruder number (E0 only)"));
    return false;
  }
  if (!cmd.fixed('S', 8, kMinTuneTargetQ8, kMaxTuneTargetQ8, &target_q8, out) ||
      !cmd.integer('C', control::Autotune::kMinCycles, control::Autotune::kMaxCycles, &cycles, out) ||
      !cmd.integer('U', 0, 1, &use, out) || !cmd.integer('F', 0, 1, &fan, out)) {
    return false;
  }
  if (refusal != nullptr) {
    out.error_line(refusal);
    return false;
  }
  bank_.begin_autotune();
  tune_.configure(kControlPeriodMs);
  if (!tune_.start(target_q8, static_cast<uint8_t>(cycles), fan != 0, control::Autotune::kMeasureAmbient, hold_gain_q8)) {  // cannot fail: checked above
    bank_.end_autotune();
    out.error_line(GCODE_TEXT("PID Autotune failed! Bad parameters"));
    return false;
  }
  target_q8_ = target_q8;
  apply_ = use != 0;
  stopped_by_fault_ = false;
  pending_ = 0;
  user_fan_ = fan_duty;
  out.print(GCODE_TEXT("PID Autotune start\n"));
  return true;
}

uint16_t AutotuneJob::step(int32_t measured_q8, uint8_t* fan_duty) {
  if (!bank_.autotuning()) {  // ended and reported: the engine's storage is the controllers' again
    *fan_duty = user_fan_;
    return 0;
  }
  const control::AutotuneOutput o = tune_.step(measured_q8);
  if (o.event == control::AutotuneEvent::kCycle) {
    cycle_ = tune_.cycle();
    pending_ |= kCycleLine;
  } else if (o.event == control::AutotuneEvent::kUltimate) {  // a cycle ended, and Ku/Tu are known
    cycle_ = tune_.cycle();
    ultimate_ = tune_.ultimate();
    pending_ |= kCycleLine | kUltimateLine;
  }
  if (o.state != control::AutotuneState::kRunning) pending_ |= kEnded;
  *fan_duty = o.state == control::AutotuneState::kRunning ? o.fan_duty : user_fan_;
  return o.duty_q16;
}

void AutotuneJob::stop(Stop why) {
  if (!running()) return;
  tune_.abort();
  stopped_by_fault_ = why == Stop::kFault;
  pending_ |= kEnded;
}

bool AutotuneJob::report(gcode::Output& out, const HandOver& now) {
  // Taken first: a control step run while these lines go out (hal::uart's TX wait) may end a
  // cycle or the tune; what it leaves is printed at the next pass.
  const uint8_t pending = pending_;
  pending_ = 0;
  const control::AutotuneCycle cycle = cycle_;
  const control::AutotuneUltimate ultimate = ultimate_;
  if (pending & kCycleLine) {
    // Marlin's per-cycle line: relay levels on the 0–255 scale, the cycle's extremes in °C.
    out.print(GCODE_TEXT(" bias: "));
    out.write_uint(cycle.bias);
    out.print(GCODE_TEXT(" d: "));
    out.write_uint(cycle.d);
    out.print(GCODE_TEXT(" min: "));
    out.write_q8(cycle.min_q8);
    out.print(GCODE_TEXT(" max: "));
    out.write_q8(cycle.max_q8);
    out.end_line();
  }
  if (pending & kUltimateLine) {
    out.print(GCODE_TEXT(" Ku: "));
    out.write_q8(ultimate.ku_q8);
    out.print(GCODE_TEXT(" Tu: "));
    out.write_q8(ultimate.tu_q8);
    out.end_line();
  }
  if ((pending & kEnded) == 0) return false;
  if (tune_.state() == control::AutotuneState::kFinished) {
    write_result(out, now);
  } else {
    write_failure(out);
  }
  // The engine's storage back to the controllers, built from the settings in force: U1's (set
  // while the bank still lent it: one configure, as for an M301), or the unchanged ones.
  bank_.end_autotune();  // (no-op if write_result did it)
  return true;
}

void AutotuneJob::write_failure(gcode::Output& out) const {
  out.print(failed_text());
  switch (tune_.failure()) {
    case control::AutotuneFailure::kTooHot: out.print(GCODE_TEXT("Temperature too high")); break;
    case control::AutotuneFailure::kTimeout: out.print(GCODE_TEXT("timeout")); break;
    case control::AutotuneFailure::kNoHeating:
      // From a hot start the probe's pulses are short and ride on the decay: hold the hotend
      // steady first (its gain then lets the probe start again: control/steady_hold.h).
      out.print(tune_.hot_start() ? GCODE_TEXT("No heating seen from a hot start: hold the target steady for 70 s (or let "
                                               "it cool), then M303 again; if it persists, check the heater and thermistor")
                                  : GCODE_TEXT("No heating: full power did not raise the temperature (heater, thermistor?)"));
      break;
    case control::AutotuneFailure::kNoOscillation:
      out.print(GCODE_TEXT("The relay oscillation did not hold around the target"));
      break;
    default:
      out.print(stopped_by_fault_ ? GCODE_TEXT("Stopped by a heater fault")
                                  : GCODE_TEXT("Aborted by the host, heater off"));
      break;
  }
  out.end_line();
}

void AutotuneJob::write_result(gcode::Output& out, const HandOver& now) {
  const control::AutotuneResult& r = tune_.result();
  control::TunedDesign d;
  if (!control::design_from_tune(r, kControlPeriodMs, &d)) {
    out.print(failed_text());
    out.print(GCODE_TEXT("Identified model outside the usable range: "));
    write_m307(out, r.model);
    return;
  }
  write_design(out, r, d);
  // State feedback + observer + dead-time predictor, designed here from the same model
  // (control/state_feedback_autodesign.h: ~400 k cycles, run right after a control step, so it
  // ends well before the next one is due).
  control::StateFeedbackConstants sf;
  const bool sf_ok = control::design_tuned_state_feedback(&d, kControlPeriodMs, &sf);
  write_sf_summary(out, sf_ok ? &sf : nullptr, d);
  const bool use_sf = sf_ok && !control::dead_time_leads(r, d);
  // "paced": designed no faster than D (hotend-sim's check of the board's M311 reads it).
  const gcode::FlashText* choice = !use_sf                    ? GCODE_TEXT("M310 S0 F1 (PID following the model's heat-up), ")
                                   : d.lag_paced && !d.two_lags ? GCODE_TEXT(", paced by D), ")
                                                                : GCODE_TEXT("), ");
  if (!apply_) {
    out.print(echo_autotune_text());
    out.print(GCODE_TEXT("not applied (U0); U1 would set the M301 above, "));
    write_choice(out, use_sf, choice, d);
    write_m307(out, d.model);
    return;
  }
  Settings next = bank_.settings();
  next.model = d.model;
  next.model_tuned = tuned_model_source(r);
  next.pid = d.pid;
  next.controller = static_cast<uint8_t>(use_sf ? ControllerId::kStateFeedback : ControllerId::kPid);
  next.feedforward = 1;
  // The constants first (S1 needs them loaded), then the settings, which take over bumplessly.
  if (sf_ok && !bank_.load_state_feedback(sf, now)) {
    return out.error_line(GCODE_TEXT("PID Autotune: the board's state-feedback constants were refused"));
  }
  if (const gcode::FlashText* refusal = bank_.apply(next, now)) return out.error_line(refusal);
  bank_.end_autotune();  // built from `next` (the lines below let a due control step run first)
  out.print(echo_autotune_text());
  out.print(GCODE_TEXT("applied (U1): "));
  write_choice(out, use_sf, choice, d);
  write_m307(out, d.model);  // the design's dead time: see control/autotune_design.h
}

}  // namespace firmware
