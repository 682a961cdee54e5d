// Matrix exponential and exact zero-order-hold discretisation with an input dead time.
// Why our own: the design must run wherever the autotune runs (maybe the firmware), so no
// library; scaling-and-squaring with a (6,6) Padé approximant is accurate to ~1e-15 relative
// once the scaled norm is <= 0.5 (Moler & Van Loan, "Nineteen dubious ways…", method 3).
#pragma once

#include "design/matrix.h"

namespace design {

inline Mat expm(const Mat& a) {
  const int n = a.rows;
  int squarings = 0;
  double scale = 1.0;
  for (double norm = norm_inf(a); norm * scale > 0.5 && squarings < 60; ++squarings) scale *= 0.5;
  const Mat x = scale * a;
  // Padé coefficients c_k = c_{k-1}·(q−k+1)/(k·(2q−k+1)), q = 6.
  const int q = 6;
  Mat num = identity(n);
  Mat den = identity(n);
  Mat xk = identity(n);
  double c = 1.0;
  for (int k = 1; k <= q; ++k) {
    c *= static_cast<double>(q - k + 1) / (k * (2 * q - k + 1));
    xk = xk * x;
    num = num + c * xk;
    den = (k % 2) ? den - c * xk : den + c * xk;
  }
  Mat e;
  if (!solve(den, num, &e)) return identity(n);  // cannot happen for norm <= 0.5 (den ~ I)
  for (int i = 0; i < squarings; ++i) e = e * e;
  return e;
}

// e^{A t} and ∫_0^t e^{A s} ds · B in one exponential of [[A, B], [0, 0]]·t (Van Loan's trick).
struct ExpIntegral {
  Mat phi;    // n×n
  Mat gamma;  // n×1
};

inline ExpIntegral exp_and_integral(const Mat& a, const Mat& b, double t_s) {
  const int n = a.rows;
  Mat aug = zeros(n + 1, n + 1);
  place(&aug, t_s * a, 0, 0);
  place(&aug, t_s * b, 0, n);
  const Mat e = expm(aug);
  ExpIntegral r;
  r.phi = block(e, 0, 0, n, n);
  r.gamma = block(e, 0, n, n, 1);
  return r;
}

// Exact ZOH model of  x' = A x + B u(t − τ)  sampled every Ts with τ = D·Ts − f, 0 <= f < Ts:
//   x[k+1] = Φ x[k] + Γa u[k−D] + Γb u[k−D+1]
// During sample interval k the plant sees u[k−D] for the first Ts − f seconds and u[k−D+1] for
// the last f seconds, hence Γb = ∫_0^f e^{As}ds B and Γa = e^{Af} ∫_0^{Ts−f} e^{As}ds B.
struct Zoh {
  Mat phi;
  Mat gamma_a;          // weight of u[k−D]
  Mat gamma_b;          // weight of u[k−D+1] (zero when τ is a whole number of periods)
  int delay = 0;        // D
  double frac_s = 0.0;  // f
};

inline Zoh discretize(const Mat& a, const Mat& b, double ts_s, double delay_s) {
  Zoh z;
  int d = 0;
  while (d * ts_s < delay_s - 1e-9 * ts_s) ++d;  // D = ceil(τ/Ts) without <cmath>
  double f = d * ts_s - delay_s;
  if (f < 1e-9 * ts_s) f = 0.0;
  z.delay = d;
  z.frac_s = f;
  const ExpIntegral whole = exp_and_integral(a, b, ts_s);
  z.phi = whole.phi;
  if (f == 0.0) {
    z.gamma_a = whole.gamma;
    z.gamma_b = zeros(a.rows, 1);
    return z;
  }
  const ExpIntegral tail = exp_and_integral(a, b, f);
  const ExpIntegral head = exp_and_integral(a, b, ts_s - f);
  z.gamma_b = tail.gamma;
  z.gamma_a = tail.phi * head.gamma;
  return z;
}

}  // namespace design
