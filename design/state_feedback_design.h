// State feedback + feedforward design for a hotend model with dead time (seed 000's structure,
// made practical): discrete model at the controller period, L by pole placement, a predictor
// over the dead time, static-gain feedforward M, and a current observer with an input-bias state.
//
// Dead time: a finite-spectrum-assignment predictor. The law acts on the state predicted D
// periods ahead, x̂[k+D|k] = Φ^D x̂[k] + Σ Φ^(j−1) Γ u[k−j], which folds into
//   u[k] = M·r − Lx·x̂[k] − Σ_{j=1..D} h_j·u[k−j] − g_d·d̂[k]
// (Lx = L·Φ^D, h_j = L·Φ^(j−1)·Γ, g_d = 1 + Σh_j because the bias is predicted to persist):
// closed-loop poles = placed poles + D poles at 0, i.e. the delay-free response, delayed.
// D is kept <= control::kSfMaxDelay by running the law every N·128 ms (N = decimation).
// Host-side double, header-only; the runtime uses the quantised constants.
#pragma once

#include "design/expm.h"
#include "design/poles.h"
#include "design/realization.h"
#include "control/state_feedback_constants.h"

namespace design {

constexpr int kMaxAug = kMaxModelStates + 1;

struct DesignOptions {
  double base_period_s = 0.128;    // firmware control period
  int decimation = 0;              // law period in 128 ms calls; 0: the smallest that fits
  double step_k = 185.0;           // design set-point step (25 → 210 °C) for the pole rule
  double rise_fraction = 16.0;     // closed-loop time constant = full-power rise time / this …
  bool search_speed = true;        // … lowered (÷1.25 steps) until the saturated nominal step
  double overshoot_limit_k = 0.2;  // overshoots no more than this
  double min_periods = 2.0;        // … but never below this many controller periods
  double observer_ratio = 4.0;     // observer poles this many times faster than the controller's
  double bias_tc_s = 0.0;          // input-bias estimate time constant; 0: the rule
  // Explicit continuous-time poles (1/s) override the rules; complex ones in conjugate pairs.
  int n_ctrl_poles = 0;
  Cplx ctrl_poles_s[kMaxAug];
  int n_obs_poles = 0;
  Cplx obs_poles_s[kMaxAug];
};

struct Design {
  const char* error = nullptr;  // null when the design succeeded
  Realization real;
  int decimation = 1;
  double ts_s = 0;
  Zoh zoh;  // Φ, Γa, Γb, D, f of the realised model
  // Controller model ξ = [x; u[k−D]] when the delay is fractional, else ξ = x.
  int n_aug = 0;
  Mat phi_aug, gamma_aug, l_aug;
  Cplx ctrl_poles_z[kMaxAug];
  // The runtime law.
  Mat lx;                      // 1×n
  double h[control::kSfMaxDelay] = {};  // h[j−1] multiplies u[k−j]
  double g_d = 1, m = 0;
  // Current observer on [x; d]:  x̂ += K·(y − C x̄), then x̄⁺ = Φ x̂ + Γa(u[k−D]+d̂) + Γb(u[k−D+1]+d̂).
  Mat phi_obs, c_obs, k_obs;  // (n+1)×(n+1), 1×(n+1), (n+1)×1
  Cplx obs_poles_z[kMaxAug];
  // Facts for initialisation and documentation.
  double dc_gain = 0;  // K per unit duty
  Mat ss_share;        // n×1: steady state per kelvin of output rise
  double t_dom_s = 0, t_rise_s = 0, t_cl_s = 0;
  double rhp_zero_s = 0;  // slowest right-half-plane zero (1/s), 0 if none
};

}  // namespace design

#include "design/state_feedback_design_impl.h"
