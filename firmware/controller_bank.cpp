#include "firmware/controller_bank.h"

#include <string.h>

#include "firmware/placement_new.h"

namespace firmware {

const gcode::FlashText* autotune_busy_text() {
  return GCODE_TEXT("Autotune running (M303): refused; M108 or M104 S0 aborts it");
}

namespace {

// Three int32 fields and no padding: bytewise equality is fieldwise equality (memcmp is smaller
// on AVR than three 32-bit compares).
static_assert(sizeof(control::PidGains) == 3 * sizeof(int32_t), "PidGains: three int32 fields, no padding");
bool same_gains(const control::PidGains& a, const control::PidGains& b) { return memcmp(&a, &b, sizeof(a)) == 0; }

// The PID family's configuration changed (M301 or M312): each configure costs ~40,000 AVR
// cycles per coefficient set, so it runs only then.
bool pid_family_changed(const Settings& a, const Settings& b) {
  return !same_gains(a.pid, b.pid) || a.fuzzy_spread_pct != b.fuzzy_spread_pct ||
         a.fuzzy_e_factor_q12 != b.fuzzy_e_factor_q12 || a.fuzzy_ec_factor_q12 != b.fuzzy_ec_factor_q12;
}

}  // namespace

// noinline: LTO inlined it into more than one caller (28 B of AVR flash as a call).
__attribute__((noinline)) void ControllerBank::init(const Settings& settings) {
  settings_ = settings;
  configure_pid_family(settings);
  feedforward_.configure(settings.model);
  reference().configure(settings.model, kControlPeriodMs);
  reset();
}

const gcode::FlashText* ControllerBank::refusal(const Settings& next, bool sf_available) const {
  if (pid_family_changed(settings_, next)) {  // the checks cost as much as configuring: only then
    if (!control::Pid::valid(next.pid, kControlPeriodMs)) return GCODE_TEXT("M301 gains beyond what the fixed-point PID holds");
    if (!control::FuzzyPid::valid(fuzzy_config(next), kControlPeriodMs))
      return GCODE_TEXT("fuzzy-PID schedule (M301 x (1 + M312 S/100)) beyond what the fixed-point PID holds");
  }
  if (!control::hotend_model_valid(next.model)) return GCODE_TEXT("M307 model out of range");
  if (!protection_valid(next)) return GCODE_TEXT("M570 values out of range");
  if (next.controller >= kControllerCount || next.feedforward > 1) return GCODE_TEXT("M310 S or F out of range");
  if (next.controller == static_cast<uint8_t>(ControllerId::kStateFeedback) && !sf_available)
    return GCODE_TEXT("M310 S1 needs state-feedback constants (M311 ... W1)");
  // The G-code commands check their own fields with the same limits first (and say which);
  // this catches what comes from EEPROM (e.g. M312 E0.025).
  if (!settings_fields_in_range(next)) return GCODE_TEXT("a setting is outside the range its G-code accepts");
  return nullptr;
}

// While M303 has the storage, only the settings change: end_autotune() configures from them.
void ControllerBank::commit(const Settings& next, const HandOver& now) {
  if (!autotuning_ && pid_family_changed(settings_, next)) configure_pid_family(next);
  if (!control::same_model(settings_.model, next.model)) {
    feedforward_.configure(next.model);
    if (!autotuning_) reference().configure(next.model, kControlPeriodMs);
  }
  settings_ = next;
  prepare_feedforward(ff_target_q8_);  // model or F may have changed
  take_over(now);
}

const gcode::FlashText* ControllerBank::apply(const Settings& next, const HandOver& now) {
  const gcode::FlashText* reason = refusal(next, sf_loaded_);
  if (reason == nullptr) commit(next, now);
  return reason;
}

const gcode::FlashText* ControllerBank::replace_all(const Settings& next, const control::StateFeedbackConstants* sf,
                                                    const HandOver& now) {
  const gcode::FlashText* reason = refusal(next, sf != nullptr);
  if (reason != nullptr) return reason;
  if (sf != nullptr && !control::state_feedback_constants_valid(*sf)) return GCODE_TEXT("state-feedback constants invalid");
  if (sf != nullptr) sf_.configure(*sf);  // checked above: cannot fail
  sf_loaded_ = sf != nullptr;
  commit(next, now);
  return nullptr;
}

bool ControllerBank::load_state_feedback(const control::StateFeedbackConstants& k, const HandOver& now) {
  if (!sf_.configure(k)) return false;  // checks first, copies only valid constants
  sf_loaded_ = true;
  if (active_id() == ControllerId::kStateFeedback) take_over(now);
  return true;
}

void ControllerBank::configure_pid_family(const Settings& s) {
  pid().configure(s.pid, kControlPeriodMs);
  fuzzy().configure(fuzzy_config(s), kControlPeriodMs);
  marlin().configure(s.pid, kControlPeriodMs);
}

// Whatever changed, the active controller continues from the present duty: a settings change
// never kicks the heater. With the heater off it starts from scratch instead.
void ControllerBank::take_over(const HandOver& now) {
  if (now.heating) {
    init_bumpless(now.measured_q8, now.duty_q16);
  } else {
    reset();
  }
}

void ControllerBank::reset() {
  ff_applied_ = false;  // the PID family's reset keeps its feedforward; refresh it at the next step
  reference_started_ = false;  // the model heats up from the next reading
  reference_holds_ = false;
  if (!autotuning_) active()->reset();
}

void ControllerBank::init_bumpless(int32_t measured_q8, uint16_t duty_q16) {
  ff_applied_ = false;  // (another controller may be active now)
  reference_started_ = false;
  reference_holds_ = true;  // no full-power heat-up at a take-over: the duty continues
  if (!autotuning_) active()->init_bumpless(measured_q8, duty_q16);
}

// noinline: LTO inlined it into more than one caller (46 B of AVR flash as a call).
__attribute__((noinline)) control::Autotune& ControllerBank::begin_autotune() {
  reset();
  autotuning_ = true;
  return *new (&shared_.tune) control::Autotune();
}

void ControllerBank::end_autotune() {
  if (!autotuning_) return;
  new (&shared_.controllers) Controllers(load_);
  autotuning_ = false;
  configure_pid_family(settings_);
  reference().configure(settings_.model, kControlPeriodMs);
  sync_staging();
  reset();  // the heater is off when a tune ends: the next target starts the controller afresh
}

void ControllerBank::sync_staging() {
  if (autotuning_) return;  // the storage is M303's now; end_autotune() refills it
  sf_staging() = sf_loaded_ ? sf_.constants() : control::StateFeedbackConstants{};
}

void ControllerBank::prepare_feedforward(int32_t target_q8) {
  ff_target_q8_ = target_q8;
  // F0 still gets the part fan's share (PID and fuzzy-PID): the fan is a measured load with a
  // known loss (M307 F), and behind a 20 s dead time feedback alone sees it 20 s late (SIMC PI:
  // 28–45 °C dips on the seeds). Marlin's PID_FAN_SCALING adds a fan term for the same reason.
  // The Marlin-style baseline keeps Marlin's default (none). Any measured model counts, also one
  // M303 left on the loose check (seed003's lag: a 29 °C dip with no recovery without it).
  uint16_t no_fan_q16 = 0;
  uint16_t full_fan_q16 = 0;
  uint16_t base_q16 = 0;
  if (settings_.feedforward != 0) {
    no_fan_q16 = feedforward_.duty_q16(target_q8, 0);
    full_fan_q16 = feedforward_.duty_q16(target_q8, 255);
  } else if (settings_.model_tuned != kModelDefault && active_id() != ControllerId::kMarlinPid) {
    base_q16 = feedforward_.duty_q16(target_q8, 0);
    full_fan_q16 = static_cast<uint16_t>(feedforward_.duty_q16(target_q8, 255) - base_q16);
  }
  // Kept for step_model_heat_up with F0 (a division per period there took the fuzzy
  // step to 2,994 cycles on seed000-5).
  base_q16_ = base_q16;
  ff_no_fan_q16_ = no_fan_q16;
  ff_fan_span_q16_ = static_cast<uint16_t>(full_fan_q16 - no_fan_q16);  // >= 0: duty_q16 grows with the fan
  follow_fan(ff_fan_);
}

// The fan's share follows the airflow (linear in it: Feedforward::duty_q16), so a fan step
// costs one multiply per period, not a prepare: span·airflow·257/2^16 = span·airflow/255
// (exact at 0 and 255); span < 2^16 and airflow·257 < 2^16, so the product fits 32 bits.
void ControllerBank::follow_fan(uint8_t airflow) {
  ff_fan_ = airflow;
  const uint32_t share = static_cast<uint32_t>(ff_fan_span_q16_) * static_cast<uint16_t>(airflow * 257u);
  const uint16_t ff_q16 = static_cast<uint16_t>(ff_no_fan_q16_ + static_cast<uint16_t>((share + 32768u) >> 16));
  if (ff_q16 != ff_q16_) ff_applied_ = false;
  ff_q16_ = ff_q16;
}

control::Controller* ControllerBank::active() {
  switch (active_id()) {
    case ControllerId::kStateFeedback: return &sf_;
    case ControllerId::kFuzzyPid: return &fuzzy();
    case ControllerId::kMarlinPid: return &marlin();
    default: return &pid();
  }
}

// Two functions so that the dispatch itself saves no registers: the state-feedback path is a
// plain tail call (its step is the longest, ~2,300 cycles on the 5-state model).
uint16_t ControllerBank::step(const control::StepInput& in) {
  if (autotuning_) return 0;  // (the control loop steps the tune instead)
  if (active_id() == ControllerId::kStateFeedback) return sf_.step(in);  // carries its own feedforward
  return step_pid_family(in);
}

__attribute__((noinline)) uint16_t ControllerBank::step_pid_family(const control::StepInput& in) {
  const ControllerId id = active_id();
  // The PID family's model feedforward (0 with M310 F0), handed over only when it changed.
  if (in.target_q8 != ff_target_q8_) prepare_feedforward(in.target_q8);
  if (in.fan_duty != ff_fan_) follow_fan(in.fan_duty);
  if (settings_.feedforward != 0 && id == ControllerId::kPid) return step_model_following(in);
  // The model heat-up with F0 wants a model whose C is not read long: fuzzy-PID's on an unsure
  // tune's (seed000-4, C 1.7 × long) overshot by 35 °C. A lag-dominated hotend's loose model is
  // fine, and without it fuzzy-PID's cut ki took minutes to build the steady duty (seed003:
  // −6.9 °C after 300 s). The fan share above takes from any measured model.
  const uint8_t source = settings_.model_tuned;
  if (id == ControllerId::kFuzzyPid && (settings_.feedforward != 0 || source == kModelMeasured || source >= kModelMeasuredLag)) {
    return step_model_heat_up(fuzzy(), fuzzy().pid(), in);
  }
  // PID F0 on fitted lags' model heats up on it too: a PI on lags of 500–1,200 s (seed000) either
  // wound up over the long heat-up (τc = L: 8.3 °C over) or crept in too slowly (τc = 2L: 0.7 °C
  // low after 1,350 s). Elsewhere PID F0 is feedback alone (heavy-slow's lag-dominated model:
  // its heat-up overshot 16 °C, where feedback ended 10 °C low).
  if (id == ControllerId::kPid && source == kModelFittedLags) return step_model_heat_up(pid(), pid(), in);
  const bool update = !ff_applied_;
  ff_applied_ = true;
  switch (id) {
    case ControllerId::kFuzzyPid:
      if (update) fuzzy().set_feedforward(ff_q16_);
      return fuzzy().step(in);
    case ControllerId::kMarlinPid:
      if (update) marlin().set_feedforward(ff_q16_);
      return marlin().step(in);
    default:
      if (update) pid().set_feedforward(ff_q16_);
      return pid().step(in);
  }
}

// PID with F1: model following (control/feedforward.h, ModelReference). The feedforward is the
// model's time-optimal heat-up, and P and I see reference − measured, so they correct only what
// the model did not predict (docs/controllers.md, feedforward). Marlin keeps the plain steady
// feedforward; fuzzy-PID runs the model only until it takes over (step_model_heat_up): both in one
// period would take its ~2,800-cycle step past the 3,000-cycle budget.
__attribute__((noinline)) uint16_t ControllerBank::step_model_following(const control::StepInput& in) {
  if (!reference_started_) reference().start(in.measured_q8, reference_holds_ ? in.target_q8 : in.measured_q8);
  reference_started_ = true;
  const control::ModelReference::Output r = reference().step(in.target_q8, ff_q16_, in.measured_q8);
  const bool update = !ff_applied_ || r.duty_q16 != model_ff_q16_;
  ff_applied_ = true;
  model_ff_q16_ = r.duty_q16;
  // While the model's heat-up runs and the hotend is below the target, P and I rest (their
  // input is the measurement itself): the model's dead time and shape differ from the plant's
  // during the transient, and integrating that difference is what overshot.
  const int32_t pid_target_q8 =
      r.reference_q8 != in.target_q8 && in.measured_q8 < in.target_q8 ? in.measured_q8 : r.reference_q8;
  if (update) pid().set_feedforward(r.duty_q16);
  return pid().step(pid_target_q8, in.measured_q8);
}

// Fuzzy-PID with a model (M310 F1, or a measured M307 with F0), and PID with F0 on fitted
// lags' model: the heat-ups and cool-downs are the model's (ModelReference: full
// power, or off, until the model's undelayed state reaches the target, then its steady duty until
// the delayed output has too), and the controller `c` takes over only then, starting from the
// model's steady duty: as the feedforward with F1, as its integral with F0 (so that the integral
// holds the target from the start and may learn a better value). `pid` is c's PID (fuzzy-PID
// drives one). Seed 002's rules act near the target, where they were designed to; far from it on
// a 20 s dead-time plant, P and I heat blind for 20 s and overshot 25–80 °C, and with F0 the
// integral (ki cut by the rules there) took minutes to build the steady duty. One of the two runs
// per period, so the step costs no more than the controller's own.
__attribute__((noinline)) uint16_t ControllerBank::step_model_heat_up(control::Controller& c, control::Pid& pid,
                                                                      const control::StepInput& in) {
  if (!reference_started_) {
    // A take-over continues bumplessly from the present duty: the model rests at the target.
    const int32_t start_q8 = reference_holds_ ? in.target_q8 : in.measured_q8;
    reference().start(start_q8, start_q8);
    reference_started_ = true;
  }
  if (!reference().holds(in.target_q8)) {
    const uint16_t base_q16 = base_q16_;  // F0: the model's steady duty (prepare_feedforward)
    const control::ModelReference::Output r = reference().step(in.target_q8, ff_q16_ + base_q16, in.measured_q8);
    // The controller waits, ready to start from the model's steady duty.
    c.reset();
    pid.set_feedforward(ff_q16_);
    pid.preset_integral(base_q16);
    ff_applied_ = true;
    return r.duty_q16;
  }
  if (!ff_applied_) pid.set_feedforward(ff_q16_);
  ff_applied_ = true;
  return c.step(in);
}

}  // namespace firmware
