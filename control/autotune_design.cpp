#include "control/autotune_design.h"

#include "control/fixed.h"
#include "control/state_feedback_autodesign.h"

namespace control {

bool tu_floors_dead_time(int32_t dead_time_q8, int32_t time_constant_q8, int32_t tu_q8) {
  const int32_t quarter_q8 = tu_q8 / 4;
  // Dead time ≤ 600 s (Q8 < 2^18): 8·D and 5·D fit; Tu/4 < 2^29 for any int32 Tu.
  return quarter_q8 > dead_time_q8 && 8 * dead_time_q8 < time_constant_q8 && 4 * quarter_q8 <= 5 * dead_time_q8;
}

namespace {

// c0 + c1·r + c2·r² + c3·r³ (Q14 coefficients, 0 ≤ r_q16 < 2^15) by Horner. For the coefficients
// below every partial sum stays under 2^16 in magnitude, so v·r < 2^31 (>> of a negative product:
// GCC's arithmetic shift, rounding down).
int32_t cubic_q14(const int32_t* c, int32_t r_q16) {
  int32_t v = c[3];
  for (int8_t i = 2; i >= 0; --i) v = c[i] + ((v * r_q16) >> 16);
  return v;
}

// Least squares in double over 0.1 ≤ r ≤ 0.5 against the exact two-point fit: C/τ1 within 0.08 %,
// D/τ2 within 0.7 % (host test: AutotuneDesign.TwoLagFopdtMatchesTheDoubleTwoPointFit).
constexpr int32_t kFopdtCOverLag1Q14[4] = {16473, -3880, 37054, -28197};
constexpr int32_t kFopdtDOverLag2Q14[4] = {17921, -9325, -26878, 38975};

}  // namespace

void two_lag_fopdt(int32_t lag1_q8, int32_t lag2_q8, int32_t* c_q8, int32_t* d_q8) {
  const int32_t r_q16 = static_cast<int32_t>(fixed::mul_div_u32(static_cast<uint32_t>(lag2_q8), 65536UL,
                                                                 static_cast<uint32_t>(lag1_q8)));
  // τ ≤ 3600 s (Q8 < 2^20) times ratios < 2^15: the 64-bit product's quotient < 2^21.
  *c_q8 = static_cast<int32_t>(fixed::mul_div_u32(static_cast<uint32_t>(lag1_q8),
                                                  static_cast<uint32_t>(cubic_q14(kFopdtCOverLag1Q14, r_q16)), 16384UL));
  *d_q8 = static_cast<int32_t>(fixed::mul_div_u32(static_cast<uint32_t>(lag2_q8),
                                                  static_cast<uint32_t>(cubic_q14(kFopdtDOverLag2Q14, r_q16)), 16384UL));
}

// noinline: LTO inlined it into more than one caller (124 B of AVR flash as a call).
__attribute__((noinline)) bool design_from_tune(const AutotuneResult& tune, uint16_t period_ms, TunedDesign* out) {
  out->model = tune.model;
  if (!hotend_model_valid(tune.model)) return false;
  // hotend_model_valid: 10 ≤ A ≤ 2000 °C, 1 ≤ C ≤ 3600 s (Q8) — the bounds below rely on it.
  const uint32_t k_q8 = static_cast<uint32_t>(tune.model.rise_q8);
  const uint32_t t_q8 = static_cast<uint32_t>(tune.model.time_constant_q8);
  int32_t l_q8 = tune.model.dead_time_q8;
  if (tu_floors_dead_time(l_q8, tune.model.time_constant_q8, tune.ultimate.tu_q8)) l_q8 = tune.ultimate.tu_q8 / 4;
  // A cut probe that peaked late (a lag the relay folded into D; not a seed000 unsure model):
  // D ≥ Tu/4. hotend40w-delay5 (host rig, 8 noise seeds at σ 0.1 °C): the relay's D (7.5–8.2 s)
  // and ×0.9 of Tu/4 settle in up to 1.42 × bound, ×1.0 in 1.07–1.16 × (overshoot ≤ 0.60 °C),
  // ×1.15 in 1.11–1.38 × (≤ 1.02 °C), longer D overshoots more (docs/autotune.md, "d held over
  // the measured cycles of a cut probe"; ×1.15 was best while d still changed between measured
  // cycles and K read 3–4 % high).
  if (tune.late_peak && !tune.unsure) {
    const int32_t lifted_q8 = tune.ultimate.tu_q8 / 4;
    if (lifted_q8 > l_q8) l_q8 = lifted_q8;
  }
  // The floors and margins lengthen a D that M307 accepted; they stop at its 600 s rather than
  // refuse the model (which would print an in-range M307 as the reason). Also keeps L < 2^18 below.
  if (l_q8 > kModelMaxDeadTimeQ8) l_q8 = kModelMaxDeadTimeQ8;
  // A lag-type hotend (the tune saw a thermistor lag): its FOPDT stands for two lags, and the
  // designs' dead-time predictor then overshoots unless L has a margin growing with lag/C:
  // L·(1 + 2.5·lag/C) (the board's state feedback on seed003, host: D 9.4 → 7.5 °C, 11.5 → 0.2,
  // 12 → 0), at least L/8: on the two-node hotends the identified D is 8–9 % below their
  // two-point fit (4.18–4.24 s against 4.59), and hotend80w undershot out of ±1 °C with it.
  // L < 2^18, 5·lag < 2^20: mul_div_u32 keeps the 64-bit product's quotient.
  out->lag_paced = false;
  if (tune.sensor_lag_q8 > 0 && l_q8 > 0) {
    int32_t margin_q8 = static_cast<int32_t>(fixed::mul_div_u32(static_cast<uint32_t>(l_q8), 5UL * static_cast<uint32_t>(tune.sensor_lag_q8), 2UL * t_q8));
    if (margin_q8 < l_q8 / 8) margin_q8 = l_q8 / 8;
    l_q8 += margin_q8;
    out->lag_paced = 20 * tune.sensor_lag_q8 <= tune.model.time_constant_q8;
  }
  // Any lag seen: two lags, provided D (after the margins) stays below C/2. Also on the two-node
  // hotends (lag ≤ C/20), where the paced one-state law, whose dead time stands for the lag,
  // overshot 0.4–1.7 °C (hotend80w 1.39–1.68 °C, 1.25–1.29 × bound; host rig, 4 noise seeds)
  // and two lags 0.02–0.19 °C, 0.95–1.11 × (docs/autotune.md, "Two lags on every lag").
  // lag_paced then only matters if the board refuses the two-lag law.
  out->two_lags = tune.sensor_lag_q8 > 0;
  // An unsure model (the probe's response outlasted the model history: seed000's higher-order
  // hotends) of no lag-type hotend: its D is short of the response's, and a D too short
  // overshoots; the more so the longer L is against C. Margin L·max(3/8, 7.5·L/C), at most L.
  // State feedback after U1 (simavr): seed000-5 (L/C ≈ 0.05: 3/8) D 73.9 → 101.6: 2.98 → 0.24 °C;
  // seed000-4 (L/C ≈ 0.086: 0.65) on the host rig over 4 noise seeds 5.9–8.0 → 0.0–1.4 °C, where
  // 3/8 gave 5.9–8.0 and ×1.5 / ×1.75 2.9–4.9 / 0 °C with 1.0–1.4 °C p-p
  // (docs/autotune.md, "Unsure models"). heavy-slow (a lag) was slower with it: not there.
  // L < 2^18 (Q8), so 15·L < 2^22 and the quotient L·15·L/(2·C) < 2^31 (C ≥ 1 s).
  if (tune.unsure && tune.sensor_lag_q8 == 0) {
    int32_t margin_q8 = static_cast<int32_t>(
        fixed::mul_div_u32(static_cast<uint32_t>(l_q8), 15UL * static_cast<uint32_t>(l_q8), 2UL * t_q8));
    if (margin_q8 < 3 * l_q8 / 8) margin_q8 = 3 * l_q8 / 8;
    if (margin_q8 > l_q8) margin_q8 = l_q8;
    l_q8 += margin_q8;
  }
  // An unsure tune whose record fits two lags (AutotuneResult::first_lag_q8, second_lag_q8;
  // τ1/10 ≤ τ2 < τ1/2): M307 (the PID rule, the model heat-up and feedforward) becomes their
  // two-point FOPDT, and the state feedback the two-lag law on τ1, τ2, paced where τ2 < τ1/5.
  // Host rig after U1 (σ 0.02 °C, 4 noise seeds), seed000-4 (τ 522–529 / 193–196 s): state
  // feedback 0.97 × bound and 0.0 °C on τ1, τ2 (the FOPDT law on C 988 s, D + margin 132 s:
  // 1.73 ×, 3.4 °C); PID + model following on M307 C τ1, D τ2 2.07–2.20 × and −0.8 to −1.2 °C
  // steady, on the two-point FOPDT (C 597–601 s, D 151–152 s) 1.03–1.13 ×, −0.26 to −0.35 °C.
  // seed000-5 (τ 1,168–1,181 / 121–122 s): the unpaced two-lag law swung 2.6 °C p-p (the ~20 s of
  // dead time the fit leaves out), paced 1.5–1.6 × and ≤ 0.06 °C (the FOPDT law on the relay's
  // C and D + margin: 1.83–1.91 ×; on the two-point FOPDT 5.7 °C of overshoot).
  const bool fitted = tune.second_lag_q8 > 0;
  if (fitted) {
    two_lag_fopdt(tune.first_lag_q8, tune.second_lag_q8, &out->model.time_constant_q8, &l_q8);
    if (out->model.time_constant_q8 > kModelMaxTimeConstantQ8) out->model.time_constant_q8 = kModelMaxTimeConstantQ8;
  }
  // (The PID rule's L ≥ 0.5 s also bounds its Kp below.)
  if (l_q8 < kMinDesignDeadTimeQ8) l_q8 = kMinDesignDeadTimeQ8;
  if (l_q8 > kModelMaxDeadTimeQ8) l_q8 = kModelMaxDeadTimeQ8;
  out->model.dead_time_q8 = l_q8;  // the feedforward's heat-up must respect the same delay
  // The state feedback's C and D: the fitted lags, else M307's, as two lags where a lag was seen
  // and D < C/2 strictly (at 2·D = C dead_time_leads already hands U1 to the PID).
  // A lag the relay confirmed: the tune's D is then the two-point dead time, above the tangent's
  // lag (a cut probe's late peak sets D to its lag).
  out->lag_pace_tenths = fitted ? (5 * tune.second_lag_q8 < tune.first_lag_q8 ? kLagPaceWide : kLagPaceDefault)
                         : tune.sensor_lag_q8 > 0 && tune.model.dead_time_q8 > tune.sensor_lag_q8 ? kLagPaceConfirmed
                                                                                                 : kLagPaceDefault;
  if (fitted) {
    out->sf_c_q8 = tune.first_lag_q8;
    out->sf_d_q8 = tune.second_lag_q8;
    out->two_lags = true;
  } else {
    out->sf_c_q8 = tune.model.time_constant_q8;
    out->sf_d_q8 = l_q8;
    if (2 * l_q8 >= tune.model.time_constant_q8) out->two_lags = false;  // l_q8 ≤ 600 s × 256: fits
  }
  const uint32_t l = static_cast<uint32_t>(l_q8);
  const uint32_t t_pid_q8 = static_cast<uint32_t>(out->model.time_constant_q8);

  // τc = 2L (smooth), or τc = L (tight) on fitted lags: there D is the two-point stand-in for a
  // second lag, not a dead time, and the smooth PI's integral (Ti = C ≈ 600 / 1,180 s) left
  // seed000-4 0.7 °C low after 1,350 s and seed000-5 not back within ±1 °C 1,400 s after the
  // fan step (simavr, HIL3's limits; docs/autotune.md, "The PID family on seed000").
  // Kp = 255·T/(K·(τc + L)) in M301 units. ratio = 255·256·T/L ≤ 65,280·921,600/128 < 2^32
  // (T ≤ 3600 s, L ≥ 0.5 s); kp_q16 = ratio·2^16/(n·K_q8), n = 3 or 2, and mul_div_u32 needs only
  // that quotient < 2^32, i.e. Kp < 65,536. n = 3: Kp ≤ 255·7200/(3·10) = 61,200. n = 2 (fitted):
  // T/L is the two-point C/D of lags with 0.1 ≤ τ2/τ1 ≤ 0.5, ≤ 9.8 (≤ 6 where both hit the
  // 3600 / 600 s caps; the 0.5 s floor only lowers it), so Kp ≤ 255·9.8/(2·10) < 125.
  const uint32_t n = fitted ? 2UL : 3UL;  // (τc + L)/L
  const uint32_t ratio = fixed::mul_div_u32(t_pid_q8, 255UL * 256UL, l);
  const uint32_t kp_q16 = fixed::mul_div_u32(ratio, 65536UL, n * k_q8);
  if (kp_q16 > static_cast<uint32_t>(Pid::kMaxKpQ16)) return false;
  // Ti = min(T, 4·(τc + L)) = min(T, 4n·L); Ki = Kp/Ti: kp_q16·256/ti_q8 ≤ Kp·2^16 fits too
  // (4n·L ≤ 12·600 s·256 < 2^21).
  const uint32_t ti_q8 = t_pid_q8 < 4UL * n * l ? t_pid_q8 : 4UL * n * l;
  const uint32_t ki_q16 = fixed::mul_div_u32(kp_q16, 256UL, ti_q8);
  out->pid = PidGains{static_cast<int32_t>(kp_q16), static_cast<int32_t>(ki_q16), 0};
  return Pid::valid(out->pid, period_ms);
}

bool design_tuned_state_feedback(TunedDesign* design, uint16_t period_ms, StateFeedbackConstants* out) {
  HotendModel m = design->model;
  m.time_constant_q8 = design->sf_c_q8;
  m.dead_time_q8 = design->sf_d_q8;
  if (design->two_lags) {
    if (design_state_feedback_two_lags(m, period_ms, out, design->lag_pace_tenths)) return true;
    // Refused: the FOPDT law on M307, and the design says so.
    design->two_lags = false;
    m = design->model;
    design->sf_c_q8 = m.time_constant_q8;
    design->sf_d_q8 = m.dead_time_q8;
  }
  return design_state_feedback_fopdt(m, period_ms, out, design->lag_paced);
}

}  // namespace control
