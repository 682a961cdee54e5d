// The state-feedback constants (what M311 uploads) designed on the board from the M307 model
// that M303 identifies: first order plus dead time, one state. Integer-only, no heap; the same
// structure and rules as the host design (design/state_feedback_design*.h +
// design/state_feedback_quantize.h, `design::design_constants(design::fopdt(K, T, L))` with the
// fan loss (F/100)/K per kelvin), which host_tests/test_state_feedback_autodesign.cpp compares
// field by field and in closed loop. docs/state_feedback.md ("Designed on the board") lists how
// each constant is computed.
//
// Set-up code for the main loop after a tune, never the control step (cycles and stack: see
// docs/state_feedback.md, "Designed on the board").
#pragma once

#include <stdint.h>

#include "control/feedforward.h"
#include "control/state_feedback_constants.h"

namespace control {

// Designs the one-state (n = 1, output_mask 1) law for `model` at the controller period
// `period_ms` (the firmware's 128 ms) into *out. False, and *out all zero (n = 0, which
// state_feedback_constants_valid and StateFeedback::configure refuse), if the model fails
// hotend_model_valid, period_ms is outside 1..1000, the dead time needs a law period beyond 250
// calls, or a constant leaves its range.
// dead_time_paced: the closed-loop time constant at least the dead time (T_cl ≥ τ, the host's
// rise_fraction = t_rise/τ where that is below 16): for a D that stands for a thermistor lag.
bool design_state_feedback_fopdt(const HotendModel& model, uint16_t period_ms, StateFeedbackConstants* out,
                                 bool dead_time_paced = false);

// Designs the two-state (n = 2, output_mask 2: y = x2) law for a thermistor that lags the block:
// the M307 model read as two lags in cascade, K/((τ1 s + 1)(τ2 s + 1)) with τ1 = C, τ2 = D and
// no dead time (the host's `design::second_order(A, C, D)`, "two lags" realisation). The host's
// pole rule with T_cl = max(t_rise/16, κ·τ2, 2h) in place of its saturation search (the search
// needs step simulations), κ = pace_tenths/10 (one of the kLagPace* below). False, and *out all
// zero, as the FOPDT design; also when D is 0 or more than C/2 (two lags that far apart only), or
// pace_tenths is 0.
bool design_state_feedback_two_lags(const HotendModel& model, uint16_t period_ms, StateFeedbackConstants* out,
                                    uint8_t pace_tenths);

// κ where the relay confirmed the heat-up's thermistor lag (the tune's two-point dead time
// replaced the tangent's: seed003): its tuned law settles in 0.73 × bound (simavr; at κ 0.6 0.92;
// the host's saturation search on the true model 0.77), and the plant does not overshoot
// (docs/autotune.md, "The two-lag law's pace").
constexpr uint8_t kLagPaceConfirmed = 4;
// κ for other lags: a cut probe's late peak, whose lag is D (heavy-slow; seed003 at σ 0.3 °C once,
// its probe cut: C 57.6 s, τ2 5.5 s, 3.9 °C over at κ 0.6, 10.9 at 0.4), and lags fitted to an
// unsure tune's record, which leaves its dead time out (seed000-4: at κ 0.4 the law swung 2.5 °C
// p-p on the host rig, 0.0–0.2 °C at 0.6).
constexpr uint8_t kLagPaceDefault = 6;
// ... fitted with τ2 < τ1/5: the dead time left out is a larger share of T_cl (seed000-5: ~20 s
// against τ2 ≈ 122 s; at 0.6·τ2 the law swung 2.6 °C p-p, at 0.8–0.9·τ2 1.5–2.3 °C, from 1.0·τ2 on
// it holds).
constexpr uint8_t kLagPaceWide = 12;

}  // namespace control
