// Continuous-time hotend models, the one model library of the design tool, the host tests and
// the simulator's plant bank:  x' = A x + B (u(t − τ) − fan·L·x),  y = C x,
// u = heater duty 0..1, fan = part-fan airflow 0..1, x and y in kelvin above ambient.
// The fan's extra heat loss enters through the heater's own path (L = fan_loss_per_k on one
// state): it cools the heated block, and in heater-duty terms it is what fan feedforward cancels.
// Host-side double, header-only.
#pragma once

#include "design/matrix.h"

namespace design {

constexpr int kMaxModelStates = 5;  // seed000's largest identified model

struct LtiModel {
  int n = 0;
  Mat a, b, c;            // n×n, n×1, 1×n
  double delay_s = 0;     // input dead time τ
  double ambient_c = 25;  // what y = 0 means
  // Extra heater-duty-equivalent loss per kelvin of rise with the part fan at 100 % (0 = unknown).
  // Two-node hotend: (0.097 − 0.068) W/K / 40 W.
  double fan_loss_per_k = 0;
  // The state whose rise the fan cools (two-node: the block, 0); −1 = the output y = C x.
  int fan_state = -1;
  // True when the states are already temperatures of similar size (lags in cascade, two-node):
  // the design keeps them. False for identified matrices, which go to modal form.
  bool physical_states = false;
};

// The fan's row L (1×n): heater-duty equivalent lost per kelvin of each state at 100 % fan.
inline Mat fan_row(const LtiModel& m) {
  if (m.fan_state >= 0) {
    Mat l = zeros(1, m.n);
    l(0, m.fan_state) = m.fan_loss_per_k;
    return l;
  }
  return m.fan_loss_per_k * m.c;
}

// A − fan·B·L: the state matrix with the part fan's airflow at `fan` (0..1).
inline Mat a_with_fan(const LtiModel& m, double fan) {
  if (fan == 0 || m.fan_loss_per_k == 0) return m.a;
  return m.a - fan * (m.b * fan_row(m));
}

// −C (A − fan·B·L)⁻¹ B: kelvin of steady rise per unit duty at a constant fan. 0 if the matrix
// is singular (integrating model).
inline double dc_gain(const LtiModel& m, double fan = 0) {
  Mat x;
  if (!solve(a_with_fan(m, fan), m.b, &x)) return 0;
  return -(m.c * x)(0, 0);
}

// The seeds' input units are their experiments' own; the plant bank rescales B so 100 % duty
// settles `rise_k` above ambient (450 K: a 40 W cartridge). Dynamics are untouched.
inline LtiModel with_dc_gain(LtiModel m, double rise_k) {
  const double g = dc_gain(m);
  if (g != 0) m.b = (rise_k / g) * m.b;
  return m;
}

// An n-state model with all matrices zero, for the builders below to fill in.
inline LtiModel zero_model(int n) {
  LtiModel m;
  m.n = n;
  m.a = zeros(n, n);
  m.b = zeros(n, 1);
  m.c = zeros(1, n);
  return m;
}

// First order plus dead time: T y' = −y + K u(t − τ). K in kelvin per unit duty.
inline LtiModel fopdt(double k_per_duty, double t_s, double tau_s) {
  LtiModel m = zero_model(1);
  m.a(0, 0) = -1.0 / t_s;
  m.b(0, 0) = k_per_duty / t_s;
  m.c(0, 0) = 1.0;
  m.delay_s = tau_s;
  m.physical_states = true;
  return m;
}

// K / ((T1 s + 1)(T2 s + 1)) as two lags in cascade (x1 = first lag, y = x2), optional dead time.
inline LtiModel second_order(double k_per_duty, double t1_s, double t2_s, double tau_s = 0) {
  LtiModel m = zero_model(2);
  m.a(0, 0) = -1.0 / t1_s;
  m.a(1, 0) = 1.0 / t2_s;
  m.a(1, 1) = -1.0 / t2_s;
  m.b(0, 0) = k_per_duty / t1_s;
  m.c(0, 1) = 1.0;
  m.delay_s = tau_s;
  m.physical_states = true;
  return m;
}

// Physical two-node hotend: heater block (heat capacity, loss to ambient) and a thermistor that
// lags the block at a first-order rate. Defaults: E3D-V6-class block with a 40 W cartridge.
struct TwoNodeParams {
  double block_j_per_k = 16.7;
  double heater_w = 40.0;
  double loss_w_per_k = 0.068;      // part fan off
  double loss_fan_w_per_k = 0.097;  // part fan at 100 %
  double sensor_rate_per_s = 0.22;  // thermistor lag: d(Ts)/dt = rate·(Tb − Ts)
};

inline LtiModel two_node(const TwoNodeParams& p = TwoNodeParams()) {
  LtiModel m = zero_model(2);  // x0 = block rise, x1 = sensor rise
  m.a(0, 0) = -p.loss_w_per_k / p.block_j_per_k;
  m.a(1, 0) = p.sensor_rate_per_s;
  m.a(1, 1) = -p.sensor_rate_per_s;
  m.b(0, 0) = p.heater_w / p.block_j_per_k;
  m.c(0, 1) = 1.0;
  m.fan_loss_per_k = (p.loss_fan_w_per_k - p.loss_w_per_k) / p.heater_w;
  m.fan_state = 0;  // the airflow cools the block, the sensor follows it
  m.physical_states = true;
  return m;
}

// Raw state-space matrices, row-major A (n×n), B (n), C (n).
inline LtiModel state_space(int n, const double* a, const double* b, const double* c,
                            double tau_s = 0) {
  LtiModel m = zero_model(n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) m.a(i, j) = a[i * n + j];
    m.b(i, 0) = b[i];
    m.c(0, i) = c[i];
  }
  m.delay_s = tau_s;
  return m;
}

}  // namespace design
