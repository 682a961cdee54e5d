#include "firmware/controller_settings.h"

#include "firmware/flash_copy.h"
#include "firmware/gcode_text.h"

namespace firmware {

// Defaults for the hotend40w plant (E3D-V6 class: block 16.7 J/K, 40 W, loss 0.068 W/K,
// sensor lag 0.22 /s), Marlin units: Kp per degC on the 0..255 scale, Ki per degC.s, Kd s.
// Chosen by a grid search (Kp 14..40, Ki 0.5..2, Kd 40..140) on a double-precision model of
// that plant under control/pid.h's structure (128 ms period, conditional integration,
// derivative on measurement, 1 s filter): the smallest worst-case overshoot over heater power
// 32..48 W, heat capacity 13..21 J/K, sensor lag 0.15..0.3 /s and targets 180..250 degC,
// among gains whose nominal 25 -> 210 degC settling into +-1 degC is <= 104 s (full power
// alone needs ~99 s). Result: nominal overshoot 0, worst 0.5 degC; part-fan step dip 1.4 degC.
// The model (M307) is the same plant's (control::kHotend40wModel); the fuzzy-PID schedule
// spreads ±50 % around the PID gains with seed 002's quantization (docs/fuzzy_pid.md).
// Feedforward starts off, so a build without M310 behaves as issue 2's firmware did.
namespace {

constexpr Settings make_default_settings() {
  Settings s{};
  s.pid = control::PidGains{34L << 16, 1L << 16, 100L << 16};
  s.model = control::kHotend40wModel;
  s.controller = kDefaultController;
  s.feedforward = 0;
  s.fuzzy_spread_pct = control::kDefaultFuzzySpreadPct;
  s.fuzzy_e_factor_q12 = control::kSeedEFactorQ12;
  s.fuzzy_ec_factor_q12 = control::kSeedEcFactorQ12;
  // Protection (issue 8, docs/protection.md): thresholds that passed every plant of the
  // simulator's bank without a false trip, with margin.
  s.model_tuned = kModelDefault;
  s.protect_tuned_c = 2;
  s.protect_default_c = 15;
  s.watch_period_s = 120;
  return s;
}

// In flash, copied out at boot and on M502: the model needs no RAM copy (16 B of .data). constexpr:
// a default that is not a constant fails to compile (a dynamic initializer would leave flash zeros).
constexpr Settings kDefaultSettings GCODE_PROGMEM = make_default_settings();

}  // namespace

Settings default_settings() {
  Settings s;
  flash_copy(&s, &kDefaultSettings, sizeof s);
  return s;
}

bool settings_fields_in_range(const Settings& s) {
  return s.pid.kp_q16 >= 0 && s.pid.ki_q16 >= 0 && s.pid.kd_q16 >= 0 && control::hotend_model_valid(s.model) &&
         s.controller < kControllerCount && s.feedforward <= 1 && s.fuzzy_spread_pct <= kMaxFuzzySpreadPct &&
         s.fuzzy_e_factor_q12 >= kMinEFactorQ12 && s.fuzzy_e_factor_q12 <= kMaxEFactorQ12 &&
         s.fuzzy_ec_factor_q12 >= kMinEcFactorQ12 && s.fuzzy_ec_factor_q12 <= kMaxEcFactorQ12 && protection_valid(s);
}

bool protection_valid(const Settings& s) {
  return s.model_tuned <= kModelFittedLags && s.protect_tuned_c >= kProtectMinC && s.protect_tuned_c <= kProtectMaxC &&
         s.protect_default_c >= kProtectMinC && s.protect_default_c <= kProtectMaxC &&
         s.watch_period_s >= kWatchMinPeriodS && s.watch_period_s <= kWatchMaxPeriodS;
}

// noinline: LTO inlined it into more than one caller (92 B of AVR flash as a call).
__attribute__((noinline)) control::FuzzyPidConfig fuzzy_config(const Settings& s) {
  control::FuzzyPidConfig c = control::fuzzy_config_around(s.pid, s.fuzzy_spread_pct);
  c.e_factor_q12 = s.fuzzy_e_factor_q12;
  c.ec_factor_q12 = s.fuzzy_ec_factor_q12;
  return c;
}

}  // namespace firmware
