// The controllers M303 designs on the board from what the tune identified (control/autotune.h),
// integer-only set-up code (no float; a few 32-bit long divisions, run once at the end of a tune):
//   - the M307 model (feedforward and model-following heat-up): the identified A, C, F, and
//     as D the dead time L below (the one the PID rule uses);
//   - PID gains: SIMC PI (Skogestad 2003, J. Process Control 13:291, Table 1) with the smooth
//     setting τc = 2·L on the identified FOPDT, Kc = T/(K·(τc + L)), Ti = min(T, 4·(τc + L)),
//     Kd = 0 — the rule the simulator's `simc` gains use (design/tuning.h, the double reference).
//     L is the identified dead time, raised to Tu/4 where tu_floors_dead_time says (below), and
//     to 1.15·Tu/4 where the tune's cut probe peaked late (AutotuneResult::late_peak).
// The fuzzy-PID's centre is the M301 gains (firmware/controller_settings.h), so it follows them.
#pragma once

#include <stdint.h>

#include "control/autotune.h"
#include "control/feedforward.h"
#include "control/pid.h"

namespace control {

struct TunedDesign {
  HotendModel model;  // M307; its dead time is the L the PID rule used
  PidGains pid;       // M301
  // A small thermistor lag (≤ C/20) folded into D: the state feedback's loop is then kept no
  // faster than D (design_state_feedback_fopdt's dead_time_paced). hotend80w's full-power rise
  // of 44 s gave T_cl 2.8 s against D 4.7: 1.30 °C of overshoot; paced 0.45 °C, 1.04 × bound.
  bool lag_paced;
};

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

}  // namespace control
