// Implementation of design_state_feedback() (see state_feedback_design.h for the structure and notation).
#pragma once

namespace design {

// Seconds for the delay-free model to rise `step_k` at 100 % duty from rest: the saturation-bound
// transient every pole choice is measured against. 0 if the model never gets there.
inline double full_power_rise_time(const LtiModel& m, double step_k) {
  Cplx ev[kMatCap];
  if (!eigenvalues(m.a, ev)) return 0;
  double fastest = 0;
  for (int i = 0; i < m.n; ++i) fastest = fabs_(ev[i].re) > fastest ? fabs_(ev[i].re) : fastest;
  double dt = fastest > 0 ? 0.05 / fastest : 0.1;
  if (dt > 0.25) dt = 0.25;
  const ExpIntegral step = exp_and_integral(m.a, m.b, dt);
  Mat x = zeros(m.n, 1);
  double y_prev = 0;
  for (long k = 1; k < 4000000L; ++k) {
    x = step.phi * x + step.gamma;
    const double y = (m.c * x)(0, 0);
    if (y >= step_k) return dt * (k - 1 + (step_k - y_prev) / (y - y_prev));
    y_prev = y;
  }
  return 0;
}

// The slowest right-half-plane zero's magnitude (1/s), 0 if none. Seed 000's identified models
// have one near 0.045/s (their step responses first dip): a loop much faster than half of it
// only buys huge gains that cancel each other (Åström & Murray, Feedback Systems, §14.3).
// Zeros are the roots of N(s) = det(sI − A + BC) − det(sI − A) (SISO, D = 0).
inline double rhp_zero_limit(const LtiModel& m) {
  const Poly den = char_poly(m.a), moved = char_poly(m.a - m.b * m.c);
  double num[kMatCap + 1] = {};
  int lead = 0;
  for (int k = 1; k <= m.n; ++k) {
    num[k] = moved.c[k] - den.c[k];
    if (lead == 0 && fabs_(num[k]) > 1e-12 * (fabs_(moved.c[k]) + fabs_(den.c[k]))) lead = k;
  }
  const int deg = lead ? m.n - lead : 0;
  if (deg < 1) return 0;
  Mat comp = zeros(deg, deg);  // companion matrix of N
  for (int j = 0; j < deg; ++j) comp(0, j) = -num[lead + 1 + j] / num[lead];
  for (int i = 1; i < deg; ++i) comp(i, i - 1) = 1.0;
  Cplx z[kMatCap];
  if (!eigenvalues(comp, z)) return 0;
  double slowest = 0;
  for (int i = 0; i < deg; ++i) {
    const double mag = sqrt_(cabs2(z[i]));
    if (z[i].re > 0 && (slowest == 0 || mag < slowest)) slowest = mag;
  }
  return slowest;
}

// Pole rule for a given closed-loop time constant T_cl (docs/state_feedback.md): real modes
// slower than T_cl are sped up by the common factor T_dom/T_cl (their spread is kept, so no
// repeated poles; capped at min_periods·Ts); faster modes and oscillatory pairs keep their
// open-loop places (no gain spent fighting them). All placed poles real and no plant zeros
// (cascade, two-node, FOPDT) → monotone linear response. Observer: same modes
// observer_ratio× faster; the input bias as below.
inline void default_poles(const Design& d, const DesignOptions& o, Cplx* ctrl_s, Cplx* obs_s) {
  const LtiModel& m = d.real.model;
  Cplx ev[kMatCap];
  eigenvalues(m.a, ev);
  const double fastest = -1.0 / (o.min_periods * d.ts_s);
  const double zero_cap = d.rhp_zero_s > 0 ? -0.5 * d.rhp_zero_s : fastest;  // stay below z/2
  const double ctrl_cap = zero_cap > fastest ? zero_cap : fastest;
  for (int i = 0; i < m.n; ++i) {
    const bool slow = ev[i].im == 0 && -1.0 / ev[i].re > d.t_cl_s;
    double s = ev[i].re * d.t_dom_s / d.t_cl_s;
    ctrl_s[i] = slow ? Cplx{s < ctrl_cap ? ctrl_cap : s, 0} : ev[i];
    // Observer: observer_ratio× faster, but with dead time no faster than 1/τ. A faster one
    // reads a wrong dead time as a state error and pushes the law (seed002, τ 10 % short:
    // 12 K overshoot with 4×, 0.02 K with 1/τ); with the model right it changes nothing.
    s *= o.observer_ratio;
    const double obs_cap = m.delay_s > 0 && -1.0 / m.delay_s > fastest ? -1.0 / m.delay_s : fastest;
    obs_s[i] = slow ? Cplx{s < obs_cap ? obs_cap : s, 0} : ev[i];
  }
  // Input-bias estimate: as fast as half the closed-loop time constant, but no faster than the
  // dead time, since the bias's effect is only seen that late. Faster only adds noise (g_d·d̂
  // grows with the predictor horizon) and turns model-gain error into overshoot.
  double bias_tc = d.t_cl_s / 2 > m.delay_s ? d.t_cl_s / 2 : m.delay_s;
  if (o.bias_tc_s > 0) bias_tc = o.bias_tc_s;
  obs_s[m.n] = {-1.0 / bias_tc, 0};
}

// Everything that does not depend on the poles: realisation, period, ZOH model, facts.
inline bool design_model(const LtiModel& model, const DesignOptions& o, Design* d) {
  if (!realize(model, &d->real)) {
    d->error = "model not realisable (order, or output weights)";
    return false;
  }
  const LtiModel& m = d->real.model;
  const int n = m.n;
  // Smallest law period N·128 ms whose dead time D fits the history and whose work fits in the
  // N calls of a period (control::state_feedback_min_decimation).
  int dec = o.decimation > 0 ? o.decimation : 2;
  for (;; ++dec) {
    d->zoh = discretize(m.a, m.b, dec * o.base_period_s, m.delay_s);
    const bool fits = d->zoh.delay <= control::kSfMaxDelay &&
                      dec >= control::state_feedback_min_decimation(static_cast<uint8_t>(d->zoh.delay));
    if (fits || o.decimation > 0 || dec > 250) break;
  }
  d->decimation = dec;
  d->ts_s = dec * o.base_period_s;
  if (d->zoh.delay > control::kSfMaxDelay) {
    d->error = "dead time longer than the input history";
    return false;
  }
  if (dec < control::state_feedback_min_decimation(static_cast<uint8_t>(d->zoh.delay))) {
    d->error = "decimation too small for the predictor's work";
    return false;
  }
  // e^{A·Ts} couples states i ← j only if j reaches i through A's graph; clear the ~1e-20
  // roundoff elsewhere so the runtime's sparse rows see exact zeros.
  bool reach[kMatCap][kMatCap] = {};
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) reach[i][j] = i == j || m.a(i, j) != 0;
  for (int k = 0; k < n; ++k)
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) reach[i][j] = reach[i][j] || (reach[i][k] && reach[k][j]);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (!reach[i][j]) d->zoh.phi(i, j) = 0;
  d->dc_gain = dc_gain(m);
  if (!(d->dc_gain > 0)) {
    d->error = "model has no positive DC gain";
    return false;
  }
  Mat g;  // steady state per unit input
  solve(identity(n) - d->zoh.phi, d->zoh.gamma_a + d->zoh.gamma_b, &g);
  d->ss_share = (1.0 / d->dc_gain) * g;
  Cplx ev[kMatCap];
  eigenvalues(m.a, ev);
  for (int i = 0; i < n; ++i)
    if (ev[i].im == 0 && -1.0 / ev[i].re > d->t_dom_s) d->t_dom_s = -1.0 / ev[i].re;
  d->t_rise_s = full_power_rise_time(m, o.step_k);
  d->rhp_zero_s = rhp_zero_limit(m);
  // Controller model: with a fractional delay, u[k−D] becomes a state and the delay D−1 periods.
  const bool frac = d->zoh.frac_s > 0;
  d->n_aug = frac ? n + 1 : n;
  d->phi_aug = zeros(d->n_aug, d->n_aug);
  d->gamma_aug = zeros(d->n_aug, 1);
  place(&d->phi_aug, d->zoh.phi, 0, 0);
  if (frac) {
    place(&d->phi_aug, d->zoh.gamma_a, 0, n);
    place(&d->gamma_aug, d->zoh.gamma_b, 0, 0);
    d->gamma_aug(n, 0) = 1.0;
  } else {
    place(&d->gamma_aug, d->zoh.gamma_a, 0, 0);
  }
  // Observer model [x; d]: the bias enters wherever the input does.
  d->phi_obs = zeros(n + 1, n + 1);
  place(&d->phi_obs, d->zoh.phi, 0, 0);
  place(&d->phi_obs, d->zoh.gamma_a + d->zoh.gamma_b, 0, n);
  d->phi_obs(n, n) = 1.0;
  d->c_obs = zeros(1, n + 1);
  place(&d->c_obs, m.c, 0, 0);
  return true;
}

// L, predictor, M and observer gain for the poles in d (ctrl_poles_z, obs_poles_z).
inline bool design_gains(Design* d) {
  const int n = d->real.model.n;
  const int dd = d->zoh.delay;
  const bool frac = d->zoh.frac_s > 0;
  const int horizon = frac ? dd - 1 : dd;
  if (!ackermann(d->phi_aug, d->gamma_aug, poly_from_roots(d->ctrl_poles_z, d->n_aug), &d->l_aug)) {
    d->error = "model not controllable";
    return false;
  }
  const Mat p = d->l_aug * power(d->phi_aug, horizon);  // L̃·Φ̃^horizon
  d->lx = block(p, 0, 0, 1, n);
  Mat lphi = d->l_aug;  // L̃·Φ̃^(j−1)
  for (int j = 1; j <= horizon; ++j) {
    d->h[j - 1] = (lphi * d->gamma_aug)(0, 0);
    lphi = lphi * d->phi_aug;
  }
  if (frac) d->h[dd - 1] += p(0, n);  // the stored u[k−D] inside ξ
  d->g_d = 1.0;
  for (int j = 0; j < dd; ++j) d->g_d += d->h[j];
  Mat c_aug = zeros(1, d->n_aug);
  place(&c_aug, d->real.model.c, 0, 0);
  Mat w;  // (I − Φ̃ + Γ̃L̃)⁻¹ Γ̃
  if (!solve(identity(d->n_aug) - d->phi_aug + d->gamma_aug * d->l_aug, d->gamma_aug, &w)) {
    d->error = "closed loop has a pole at z = 1";
    return false;
  }
  d->m = 1.0 / (c_aug * w)(0, 0);
  // Current observer: error dynamics eig(Φo − K·Co·Φo), placed on the dual system.
  Mat kt;
  if (!ackermann(transpose(d->phi_obs), transpose(d->c_obs * d->phi_obs),
                 poly_from_roots(d->obs_poles_z, n + 1), &kt)) {
    d->error = "model not observable from the sensor";
    return false;
  }
  d->k_obs = transpose(kt);
  return true;
}

// Overshoot (K) of the nominal design step with the heater clamped to 0..1: the discrete model
// itself as plant, the state known exactly (a converged observer stays exact on its own model).
inline double saturated_step_overshoot(const Design& d, double step_k) {
  const int n = d.real.model.n;
  const int dd = d.zoh.delay;
  double x[kMatCap] = {}, hist[control::kSfMaxDelay + 1] = {}, peak = 0;
  const double horizon_s = 3 * d.t_rise_s + d.real.model.delay_s + 20 * d.t_cl_s;
  for (long k = 0; k * d.ts_s < horizon_s; ++k) {
    double v = d.m * step_k;
    for (int i = 0; i < n; ++i) v -= d.lx(0, i) * x[i];
    for (int j = 1; j <= dd; ++j) v -= d.h[j - 1] * hist[j];
    hist[0] = v < 0 ? 0 : (v > 1 ? 1 : v);
    const double ua = hist[dd], ub = dd > 0 ? hist[dd - 1] : hist[0];
    double next[kMatCap], y = 0;
    for (int i = 0; i < n; ++i) {
      next[i] = d.zoh.gamma_a(i, 0) * ua + d.zoh.gamma_b(i, 0) * ub;
      for (int j = 0; j < n; ++j) next[i] += d.zoh.phi(i, j) * x[j];
    }
    for (int i = 0; i < n; ++i) {
      x[i] = next[i];
      y += d.real.model.c(0, i) * x[i];
    }
    for (int j = control::kSfMaxDelay; j >= 1; --j) hist[j] = hist[j - 1];
    if (y - step_k > peak) peak = y - step_k;
  }
  return peak;
}

// Small steps saturate for less time and land differently (seed000-4 overshoots most at 75 K):
// the rule checks a spread of steps up to the design step.
inline double worst_step_overshoot(const Design& d, double step_k) {
  const double fractions[] = {1.0, 0.7, 0.5, 0.35, 0.25, 0.15};
  double worst = 0;
  for (double f : fractions) {
    const double o = saturated_step_overshoot(d, f * step_k);
    worst = o > worst ? o : worst;
  }
  return worst;
}

inline Design design_for_tcl(const LtiModel& model, const DesignOptions& o, double t_cl_s) {
  Design d;
  if (!design_model(model, o, &d)) return d;
  const int n = d.real.model.n;
  d.t_cl_s = t_cl_s > o.min_periods * d.ts_s ? t_cl_s : o.min_periods * d.ts_s;
  if (d.rhp_zero_s > 0 && d.t_cl_s < 2.0 / d.rhp_zero_s) d.t_cl_s = 2.0 / d.rhp_zero_s;
  Cplx ctrl_s[kMaxAug], obs_s[kMaxAug];
  default_poles(d, o, ctrl_s, obs_s);
  if (o.n_ctrl_poles == n)
    for (int i = 0; i < n; ++i) ctrl_s[i] = o.ctrl_poles_s[i];
  if (o.n_obs_poles == n + 1)
    for (int i = 0; i <= n; ++i) obs_s[i] = o.obs_poles_s[i];
  for (int i = 0; i < n; ++i) d.ctrl_poles_z[i] = z_of_s(ctrl_s[i], d.ts_s);
  if (d.n_aug > n) d.ctrl_poles_z[n] = {0, 0};  // the stored input needs no dynamics: deadbeat
  for (int i = 0; i <= n; ++i) d.obs_poles_z[i] = z_of_s(obs_s[i], d.ts_s);
  design_gains(&d);
  return d;
}

// The design: the fastest closed loop (T_cl = rise time / rf, rf from rise_fraction down) whose
// saturated nominal step overshoots <= overshoot_limit_k. With one slow state any speed is fine
// (landing only lowers the duty); with several, heat already stored in the block must be braked
// with the heater at 0 %, and a law that is too fast asks for negative power and overshoots.
inline Design design_state_feedback(const LtiModel& model, const DesignOptions& o = DesignOptions()) {
  Design probe;
  if (!design_model(model, o, &probe)) return probe;
  const double base = probe.t_rise_s > 0 ? probe.t_rise_s : probe.t_dom_s;
  if (o.n_ctrl_poles > 0 || !o.search_speed)
    return design_for_tcl(model, o, base / o.rise_fraction);
  Design d;
  for (double rf = o.rise_fraction; rf >= 1.0; rf /= 1.25) {
    d = design_for_tcl(model, o, base / rf);
    if (d.error) return d;
    if (worst_step_overshoot(d, o.step_k) <= o.overshoot_limit_k) return d;
  }
  return d;
}

}  // namespace design
