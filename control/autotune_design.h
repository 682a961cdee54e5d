// The controllers M303 designs on the board from what the tune identified (control/autotune.h),
// integer-only set-up code (no float; a few 32-bit long divisions, run once at the end of a tune):
//   - the M307 model (feedforward and model-following heat-up): the identified A, C, F, and
//     as D the dead time L below (the one the PID rule uses);
//   - PID gains: SIMC PI (Skogestad 2003, J. Process Control 13:291, Table 1) with the smooth
//     setting τc = 2·L on the identified FOPDT, Kc = T/(K·(τc + L)), Ti = min(T, 4·(τc + L)),
//     Kd = 0 — the rule the simulator's `simc` gains use (design/tuning.h, the double reference);
//     on an unsure tune's fitted lags (M307 their two-point FOPDT) the tight τc = L (`simc-tight`).
//     L is the identified dead time, raised to Tu/4 where tu_floors_dead_time says (below), and
//     to Tu/4 where the tune's cut probe peaked late (AutotuneResult::late_peak).
// The fuzzy-PID's centre is the M301 gains (firmware/controller_settings.h), so it follows them.
#pragma once

#include <stdint.h>

#include "control/autotune.h"
#include "control/feedforward.h"
#include "control/pid.h"
#include "control/state_feedback_constants.h"

namespace control {

struct TunedDesign {
  HotendModel model;  // M307; its dead time is the L the PID rule used
  PidGains pid;       // M301
  // A small thermistor lag (≤ C/20) folded into D: should the board refuse the two-lag law, the
  // one-state loop is kept no faster than D (design_state_feedback_fopdt's dead_time_paced).
  // hotend80w's full-power rise of 44 s gave T_cl 2.8 s against D 4.7: 1.30 °C of overshoot.
  bool lag_paced;
  // The tune saw a thermistor lag (and D < C/2): the state feedback is the two-state design of
  // two lags τ1 = C, τ2 = D (design_state_feedback_two_lags). Host rig after U1, noise seeds
  // 12345, 1–3: seed003 2.06–2.13 → 0.86–0.89 × bound (0.71–0.73 at κ 0.4, lag_pace_tenths), heavy-slow 1.68–1.70 → 0.98–1.01 ×
  // (docs/autotune.md, "Design"); on the two-node hotends (lag ≤ C/20) overshoot 0.4–1.7 → ≤ 0.2 °C
  // at 0.95–1.11 × (paced: 1.04–1.29 ×). Not without a lag seen (hotend40w-delay5: a transport
  // delay, which two lags without dead time oscillate on).
  bool two_lags;
  // The two-lag law's pace κ in tenths (T_cl ≥ κ·τ2, design_state_feedback_two_lags): kLagPaceConfirmed
  // where the relay confirmed the heat-up's lag, kLagPaceWide on lags fitted with τ2 < τ1/5, else
  // kLagPaceDefault.
  uint8_t lag_pace_tenths;
  // The C and D the state feedback is designed on (s × 256): two lags τ1, τ2 where two_lags.
  // M307's C and D, except after an unsure tune's two-lag fit: there M307 holds the lags'
  // two-point FOPDT, and these are τ1, τ2.
  int32_t sf_c_q8, sf_d_q8;
};

// The two-point FOPDT (28.3 % and 63.2 % of the step, Smith's method: the fit hotend-sim gives
// the bank's step responses) of two lags τ1 > τ2 with 0.1 ≤ τ2/τ1 ≤ 0.5 (the fit's acceptance,
// AutotuneResult::second_lag_q8), all s × 256: C/τ1 and D/τ2 as cubics in r = τ2/τ1, least
// squares over that range, within 0.08 % / 0.7 % of the exact fit. τ1 ≤ 3600 s.
void two_lag_fopdt(int32_t lag1_q8, int32_t lag2_q8, int32_t* c_q8, int32_t* d_q8);

// The shortest dead time the PID rule accepts (s × 256): below it the SIMC gain would grow
// past anything a 128 ms loop with a lagging thermistor can use.
constexpr int32_t kMinDesignDeadTimeQ8 = 128;  // 0.5 s

// Whether the relay's Tu/4 replaces the identified dead time D (all Q8): only where
// D < Tu/4 ≤ 1.25·D and D/C < 1/8. A longer quarter period can mean a lag folded into too short
// a D (hotend40w-delay5), but the relay's own switching lengthens Tu by 3–45 % on FOPDT plants,
// and a D too long slows or overshoots the state feedback (measured: docs/autotune.md, "Design").
bool tu_floors_dead_time(int32_t dead_time_q8, int32_t time_constant_q8, int32_t tu_q8);

// False if the identified model is outside what M307 accepts or the gains fall outside
// Pid::valid (nothing in *out is meaningful then).
bool design_from_tune(const AutotuneResult& tune, uint16_t period_ms, TunedDesign* out);

// The state feedback U1 loads for `design`: the two-lag law where design->two_lags, else the
// FOPDT's (paced where lag_paced). A two-lag design the board refuses falls back to the FOPDT's
// and clears two_lags, so the flag always says what *out holds. False: neither designs it.
bool design_tuned_state_feedback(TunedDesign* design, uint16_t period_ms, StateFeedbackConstants* out);

// Which controller M303 U1 selects (measured over the plant bank, docs/bench): state feedback
// unless the dead time is at least half the time constant, or at least an eighth of it with no
// thermistor lag seen; there the PID following the model's heat-up overshot less (seed002: 0.02
// vs 1.69 °C; fopdt-delay25 with D 3 % short: 0.28 vs 2.63 °C, 0.99 vs 1.40 × bound). With a
// lag (seed003, heavy-slow, hotend40w-delay5) it was the other way round.
// An unsure model without a lag is judged by its identified D, not by the margin design_from_tune
// gave it: the PID following seed000's model heat-up overshot 31–48 °C (its C is read long).
inline bool dead_time_leads(const AutotuneResult& tune, const TunedDesign& design) {
  // ≤ 600 s × 256 (M307's bound): 8× fits int32
  // (A second lag from the unsure tune's fit counts as a lag: design D is then τ2.)
  const bool lag = tune.sensor_lag_q8 > 0 || tune.second_lag_q8 > 0;
  const int32_t dead_q8 = tune.unsure && !lag ? tune.model.dead_time_q8 : design.model.dead_time_q8;
  return 2 * dead_q8 >= design.model.time_constant_q8 || (!lag && 8 * dead_q8 >= design.model.time_constant_q8);
}

// Whether the protection's model check may bound the heater tightly by the tuned model (M307's
// "measured" flag). Not after a hot start: its loss and time constant come from a short decay
// (fopdt-fast after M109 S200: C 39 s for 30 s), and the tight check tripped on the next
// heat-up. Not for a lag-dominated hotend (thermistor lag > 5 % of C): a FOPDT reaches its full
// slope sooner than two lags do, and the tight check tripped on seed003's first heat-up. Not for
// a model from a probe whose response outlasted the history (seed000-4: D 44 s against a 163 s
// dead time): tight bounds from it tripped on the first heat-up.
inline bool tune_bounds_tightly(const AutotuneResult& tune) {
  return !tune.hot_start && 20 * tune.sensor_lag_q8 <= tune.model.time_constant_q8 && !tune.unsure;
}

// Whether a heat-up may follow the tuned model (fuzzy-PID with M310 F0 does): not after a hot
// start or an unsure tune, whose C may be read long (fopdt-fast after M109 S200: 39 s for 30 s;
// seed000-4: 1.7 ×), so that full power would stay on too long. An unsure tune whose record fit
// two lags has M307 from them (design_from_tune), not that long C (the firmware gives that one a
// source of its own, firmware::kModelFittedLags, on which PID F0 follows the heat-up too).
inline bool tune_heat_up_trusted(const AutotuneResult& tune) {
  return !tune.hot_start && (!tune.unsure || tune.second_lag_q8 > 0);
}

}  // namespace control
