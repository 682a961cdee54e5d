// The controllers M303 designs on the board from what the tune identified (control/autotune.h),
// integer-only set-up code (no float; a few 32-bit long divisions, run once at the end of a tune):
//   - the M307 model (feedforward and model-following heat-up): the identified A, C, F, and
//     as D the dead time L below (the one the PID rule uses);
//   - PID gains: SIMC PI (Skogestad 2003, J. Process Control 13:291, Table 1) with the smooth
//     setting τc = 2·L on the identified FOPDT, Kc = T/(K·(τc + L)), Ti = min(T, 4·(τc + L)),
//     Kd = 0 — the rule the simulator's `simc` gains use (design/tuning.h, the double reference).
//     L is the larger of the identified dead time and Tu/4: a FOPDT's ultimate period lies
//     between 2L (pure dead time) and 4L (pure lag), so Tu/4 never exceeds a true FOPDT's dead
//     time, while on lag-type hotends (thermistor behind the block) it supplies the equivalent
//     dead time the relay saw and the heat-up's tangent cannot.
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
};

// The shortest dead time the PID rule accepts (s × 256): below it the SIMC gain would grow
// past anything a 128 ms loop with a lagging thermistor can use.
constexpr int32_t kMinDesignDeadTimeQ8 = 128;  // 0.5 s

// False if the identified model is outside what M307 accepts or the gains fall outside
// Pid::valid (nothing in *out is meaningful then).
bool design_from_tune(const AutotuneResult& tune, uint16_t period_ms, TunedDesign* out);

}  // namespace control
