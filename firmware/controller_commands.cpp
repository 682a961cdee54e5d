#include "firmware/controller_commands.h"

#include <stddef.h>
#include <string.h>

#include "control/state_feedback_gcode.h"
#include "firmware/flash_copy.h"

namespace firmware {
namespace {

// The start of the settings echoes, one copy in flash for its five senders.
const gcode::FlashText* echo_text() { return GCODE_TEXT("echo:"); }

// value / 2^frac_bits with the fewest decimals (2..4) that parse back to the same value, so
// that the default factors read "0.40" and "0.60" while any other value still round-trips.
// Report-time only: the divisions are not in the control step.
void write_round_trip(gcode::Output& out, uint16_t value, uint8_t frac_bits) {
  uint32_t scale = 100;
  uint8_t decimals = 2;
  for (; decimals < 4; ++decimals, scale *= 10) {
    const uint32_t printed = (uint32_t{value} * scale + (1UL << (frac_bits - 1))) >> frac_bits;
    const uint32_t parsed = ((printed << frac_bits) + scale / 2) / scale;
    if (parsed == value) break;
  }
  out.write_fixed(value, frac_bits, decimals);
}

const gcode::FlashText* controller_name(ControllerId id) {
  switch (id) {
    case ControllerId::kStateFeedback: return GCODE_TEXT("state feedback");
    case ControllerId::kFuzzyPid: return GCODE_TEXT("fuzzy-PID");
    case ControllerId::kMarlinPid: return GCODE_TEXT("Marlin PID");
    default: return GCODE_TEXT("PID");
  }
}

// Any parameter letter from `first` to `last` present (letters as a range, not a string
// literal: avr-gcc would copy the literal into RAM).
bool has_any(const gcode::Command& cmd, char first, char last) {
  for (char c = first; c <= last; ++c)
    if (cmd.has(c)) return true;
  return false;
}

// One setting a parameter letter edits: where it lives in Settings, its width (1 or 2 bytes
// unsigned, or int32) and what the command accepts (Command::fixed prints these bounds).
// Tables of these in flash replace a call with ten constant arguments per letter (~500 B).
struct SettingParam {
  char letter;
  uint8_t frac_bits;
  uint8_t offset;
  uint8_t bytes;
  int32_t lo;
  int32_t hi;
};

#define SETTING_PARAM(letter, frac_bits, field, lo, hi)                                          \
  SettingParam {                                                                                \
    letter, frac_bits, static_cast<uint8_t>(offsetof(Settings, field)),                         \
        static_cast<uint8_t>(sizeof(static_cast<Settings*>(nullptr)->field)), lo, hi            \
  }

const SettingParam kModelParams[] GCODE_PROGMEM = {  // M307
    SETTING_PARAM('A', 8, model.rise_q8, control::kModelMinRiseQ8, control::kModelMaxRiseQ8),
    SETTING_PARAM('C', 8, model.time_constant_q8, control::kModelMinTimeConstantQ8,
                  control::kModelMaxTimeConstantQ8),
    SETTING_PARAM('D', 8, model.dead_time_q8, 0, control::kModelMaxDeadTimeQ8),
    SETTING_PARAM('F', 8, model.fan_loss_pct_q8, 0, control::kModelMaxFanLossPctQ8)};
const SettingParam kSelectParams[] GCODE_PROGMEM = {  // M310
    SETTING_PARAM('S', 0, controller, 0, kControllerCount - 1), SETTING_PARAM('F', 0, feedforward, 0, 1)};
const SettingParam kFuzzyParams[] GCODE_PROGMEM = {  // M312
    SETTING_PARAM('S', 0, fuzzy_spread_pct, 0, kMaxFuzzySpreadPct),
    SETTING_PARAM('E', 12, fuzzy_e_factor_q12, kMinEFactorQ12, kMaxEFactorQ12),
    SETTING_PARAM('C', 12, fuzzy_ec_factor_q12, kMinEcFactorQ12, kMaxEcFactorQ12)};
const SettingParam kProtectionParams[] GCODE_PROGMEM = {  // M570
    SETTING_PARAM('T', 0, protect_tuned_c, kProtectMinC, kProtectMaxC),
    SETTING_PARAM('U', 0, protect_default_c, kProtectMinC, kProtectMaxC),
    SETTING_PARAM('P', 0, watch_period_s, kWatchMinPeriodS, kWatchMaxPeriodS),
    SETTING_PARAM('S', 0, model_tuned, kModelDefault, kModelFittedLags)};
#undef SETTING_PARAM

// Every parameter of the table checked (the first bad one gets its Error line and nothing
// changes), then, if any was given, the edited copy applied. False when none was given: the
// caller reports instead. `model_measured`: M307 marks the model as the host's (model_tuned).
bool edit_settings(ControllerBank& bank, const gcode::Command& cmd, gcode::Output& out, const HandOver& now,
                   const SettingParam* table, uint8_t count, bool model_measured) {
  Settings next = bank.settings();
  bool given = false;
  for (uint8_t i = 0; i < count; ++i) {
    SettingParam param;
    flash_copy(&param, &table[i], sizeof param);
    uint8_t* field = reinterpret_cast<uint8_t*>(&next) + param.offset;
    int32_t value = 0;  // little-endian on both targets: 1- and 2-byte fields are unsigned
    memcpy(&value, field, param.bytes);
    if (!cmd.fixed(param.letter, param.frac_bits, param.lo, param.hi, &value, out)) return true;
    memcpy(field, &value, param.bytes);
    given = given || cmd.has(param.letter);
  }
  if (!given) return false;
  // M307 (the host vouches for its model) makes it measured: the model check gets tight (M570 T).
  // M570 S sets the model's source as is (M503 prints it after M307, so a replay restores it).
  if (model_measured) next.model_tuned = kModelMeasured;
  out.refusal_line(bank.apply(next, now));
  return true;
}

template <uint8_t N>
constexpr uint8_t count_of(const SettingParam (&)[N]) {
  return N;
}

}  // namespace

// noinline: LTO inlined it into more than one caller (72 B of AVR flash as a call).
__attribute__((noinline)) bool ControllerCommands::handle(const gcode::Command& cmd, gcode::Output& out, const HandOver& now) {
  const bool ours = cmd.letter == 'M' && ((cmd.code >= 307 && cmd.code <= 312 && cmd.code != 308 && cmd.code != 309) ||
                                          cmd.code == 570);
  if (!ours) return false;
  if (!cmd.valid(out)) return true;
  switch (cmd.code) {
    case 570: protection(cmd, out, now); break;
    case 307: model(cmd, out, now); break;
    case 310: select(cmd, out, now); break;
    case 311: upload(cmd, out, now); break;
    default: fuzzy(cmd, out, now); break;
  }
  return true;
}

void ControllerCommands::model(const gcode::Command& cmd, gcode::Output& out, const HandOver& now) {
  if (edit_settings(bank_, cmd, out, now, kModelParams, count_of(kModelParams), true)) return;
  out.print(echo_text());
  write_model(out);
}

void ControllerCommands::select(const gcode::Command& cmd, gcode::Output& out, const HandOver& now) {
  if (edit_settings(bank_, cmd, out, now, kSelectParams, count_of(kSelectParams), false)) return;
  out.print(echo_text());
  write_selection(out);
}

// noinline: LTO inlined it into more than one caller (172 B of AVR flash as a call).
__attribute__((noinline)) void ControllerCommands::upload(const gcode::Command& cmd, gcode::Output& out, const HandOver& now) {
  if (*cmd.params == '\0') return write_upload(out, echo_text());
  if (bank_.autotuning()) return out.error_line(autotune_busy_text());  // (the machine refuses it first)
  control::StateFeedbackConstants& staging = bank_.sf_staging();
  int32_t commit = 0;
  if (!cmd.integer('W', 1, 1, &commit, out)) return;
  int32_t previous[control::kSfFieldsPerLine];  // this line's fields before it: a refusal restores them
  int32_t first = 0;
  const bool writes = has_any(cmd, 'A', 'H');
  if (writes) {
    if (!cmd.require('I', out) || !cmd.integer('I', 0, control::kSfFieldCount - 1, &first, out)) return;
    // Check the whole line first, then write it: the second pass reads each value again (it
    // passed the first), which keeps a second array of 8 values off the stack.
    for (uint8_t pass = 0; pass < 2; ++pass) {
      for (uint8_t j = 0; j < control::kSfFieldsPerLine; ++j) {
        const char letter = static_cast<char>('A' + j);
        if (!cmd.has(letter)) continue;
        const control::SfField field = control::sf_field(staging, static_cast<uint8_t>(first + j));
        if (field.address == nullptr) {
          out.print(GCODE_TEXT("Error:M311 "));
          out.write_char(letter);
          out.print(GCODE_TEXT(": field index beyond "));
          out.write_uint(control::kSfFieldCount - 1);
          return out.end_line();
        }
        int32_t lo, hi, value;
        control::sf_field_range(field.type, &lo, &hi);
        if (!cmd.fixed(letter, 0, lo, hi, &value, out)) return;
        if (pass == 1) {
          previous[j] = control::sf_get(field);
          control::sf_set(field, value);
        }
      }
    }
  }
  if (commit == 1 && !bank_.load_state_feedback(staging, now)) {
    // A refused command changes nothing: a later W1 must not commit this line's fields.
    for (uint8_t j = 0; writes && j < control::kSfFieldsPerLine; ++j) {
      if (cmd.has(static_cast<char>('A' + j)))
        control::sf_set(control::sf_field(staging, static_cast<uint8_t>(first + j)), previous[j]);
    }
    out.error_line(GCODE_TEXT("M311 W1: constants invalid (ranges, or a product beyond 32 bits), nothing applied"));
  }
}

void ControllerCommands::fuzzy(const gcode::Command& cmd, gcode::Output& out, const HandOver& now) {
  if (edit_settings(bank_, cmd, out, now, kFuzzyParams, count_of(kFuzzyParams), false)) return;
  out.print(echo_text());
  write_fuzzy(out);
}

void ControllerCommands::sync_staging() { bank_.sync_staging(); }

// M570 T<°C> U<°C> P<s> S<0..4>: the protection's thresholds (RepRapFirmware's M570 and Prusa's
// M310 set heater-fault detection; the letters here are our own). S is the model's source
// (ModelSource: 0 default, 1 measured, 2 loose, 3 lag-dominated, 4 fitted lags), which decides whether T or U
// applies: M307 and M303 set it, and M503 prints it after M307 so that replaying M503 restores a
// default, loose or lag-dominated model as it was. All checked first.
void ControllerCommands::protection(const gcode::Command& cmd, gcode::Output& out, const HandOver& now) {
  if (edit_settings(bank_, cmd, out, now, kProtectionParams, count_of(kProtectionParams), false)) return;
  out.print(echo_text());
  write_protection(out);
}

void ControllerCommands::write_protection(gcode::Output& out) const {
  const Settings& s = bank_.settings();
  out.print(GCODE_TEXT("M570 T"));
  out.write_int(s.protect_tuned_c);
  out.print(GCODE_TEXT(" U"));
  out.write_int(s.protect_default_c);
  out.print(GCODE_TEXT(" P"));
  out.write_int(s.watch_period_s);
  out.print(GCODE_TEXT(" S"));
  out.write_int(s.model_tuned);
  out.print(s.model_tuned == kModelMeasured ? GCODE_TEXT(" ; model check: T (measured model)\n")
                                            : GCODE_TEXT(" ; model check: U (default, loose or lag-dominated model)\n"));
}

void ControllerCommands::report(gcode::Output& out) {
  out.print(GCODE_TEXT("echo:; Hotend model (M307 A rise at 100 % degC, C time constant s, D dead time s, F fan loss %):\n"
                       "echo:  "));
  write_model(out);
  out.print(GCODE_TEXT("echo:; Fuzzy-PID around M301 (M312 S spread %, E/C quantization factors):\necho:  "));
  write_fuzzy(out);
  out.print(GCODE_TEXT("echo:; State-feedback constants (M311):\n"));
  write_upload(out, GCODE_TEXT("echo:  "));
  out.print(GCODE_TEXT("echo:; Controller (M310 S0 PID, S1 state feedback, S2 fuzzy-PID, S3 Marlin PID; F1 model feedforward):\n"
                       "echo:  "));
  write_selection(out);
  out.print(GCODE_TEXT("echo:; Heater protection (M570 T model check degC, U with the default model degC, P watch window s, S model: 0 default, 1 measured (T applies), 2 loose, 3 lag-dominated, 4 fitted lags):\n"
                       "echo:  "));
  write_protection(out);
}

void ControllerCommands::write_model(gcode::Output& out) const { write_m307(out, bank_.settings().model); }

// Each value as it reads back exactly (Output::write_exact): the M503 line replays exactly, and
// the tune's model can be recomputed on a host bit for bit.
void write_m307(gcode::Output& out, const control::HotendModel& m) {
  const int32_t values[4] = {m.rise_q8, m.time_constant_q8, m.dead_time_q8, m.fan_loss_pct_q8};
  out.print(GCODE_TEXT("M307"));
  for (uint8_t i = 0; i < 4; ++i) {
    out.write_char(' ');
    out.write_char(static_cast<char>(i == 0 ? 'A' : (i == 1 ? 'C' : (i == 2 ? 'D' : 'F'))));
    out.write_exact(values[i], 8);
  }
  out.end_line();
}

void ControllerCommands::write_selection(gcode::Output& out) const {
  const Settings& s = bank_.settings();
  out.print(GCODE_TEXT("M310 S"));
  out.write_uint(s.controller);
  out.print(GCODE_TEXT(" F"));
  out.write_uint(s.feedforward);
  out.print(GCODE_TEXT(" ; "));
  out.print(controller_name(bank_.active_id()));
  out.end_line();
}

void ControllerCommands::write_fuzzy(gcode::Output& out) const {
  const Settings& s = bank_.settings();
  out.print(GCODE_TEXT("M312 S"));
  out.write_uint(s.fuzzy_spread_pct);
  out.print(GCODE_TEXT(" E"));
  write_round_trip(out, s.fuzzy_e_factor_q12, 12);
  out.print(GCODE_TEXT(" C"));
  write_round_trip(out, s.fuzzy_ec_factor_q12, 12);
  out.end_line();
}

void ControllerCommands::write_upload(gcode::Output& out, const gcode::FlashText* prefix) const {
  if (!bank_.state_feedback_loaded()) {
    out.print(prefix);
    return out.print(GCODE_TEXT("M311 ; no state-feedback constants loaded\n"));
  }
  // Straight to the output (control/state_feedback_gcode.h's line buffer and integer formatter
  // cost ~300 B of AVR flash beside Output's own).
  struct Sink {
    gcode::Output& out;
    const gcode::FlashText* prefix;
    void begin_line(uint8_t first) {
      out.print(prefix);
      out.print(GCODE_TEXT("M311 I"));
      out.write_uint(first);
    }
    void field(char letter, int32_t value) {
      out.write_char(' ');
      out.write_char(letter);
      out.write_int(value);
    }
    void end_line() { out.end_line(); }
    void commit_line() {
      out.print(prefix);
      out.print(GCODE_TEXT("M311 W1\n"));
    }
  };
  Sink sink{out, prefix};
  control::write_state_feedback_lines(bank_.state_feedback_constants(), sink);
}

}  // namespace firmware
