// Pole placement tools: polynomials from roots, characteristic polynomials, Ackermann's formula.
// Ackermann (L = e_nᵀ 𝒞⁻¹ α(Φ)) is what seed 000 used; it is ill-conditioned for large n, but
// our models have at most 6 states and the tests check the placed polynomial to 1e-6.
#pragma once

#include "design/eigen.h"

namespace design {

// Monic polynomial z^n + c[1] z^(n−1) + … + c[n]; c[0] = 1.
struct Poly {
  int degree = 0;
  double c[kMatCap + 1] = {1.0};
};

// Real coefficients from roots; complex roots must come with their conjugates.
inline Poly poly_from_roots(const Cplx* roots, int n) {
  Poly p;
  Cplx acc[kMatCap + 1] = {{1.0, 0.0}};
  for (int k = 0; k < n; ++k) {
    for (int i = k + 1; i >= 1; --i) {  // acc := acc·(z − root)
      const Cplx prod = cmul(acc[i - 1], roots[k]);
      acc[i].re -= prod.re;
      acc[i].im -= prod.im;
    }
  }
  p.degree = n;
  for (int i = 0; i <= n; ++i) p.c[i] = acc[i].re;
  return p;
}

// det(zI − A) by Faddeev–LeVerrier (exact in exact arithmetic, fine for n <= 8).
inline Poly char_poly(const Mat& a) {
  const int n = a.rows;
  Poly p;
  p.degree = n;
  Mat m = identity(n);
  for (int k = 1; k <= n; ++k) {
    const Mat am = a * m;
    double tr = 0;
    for (int i = 0; i < n; ++i) tr += am(i, i);
    p.c[k] = -tr / k;
    m = am + p.c[k] * identity(n);
  }
  return p;
}

// α(A) = A^n + c1 A^(n−1) + … + cn I by Horner.
inline Mat poly_of_matrix(const Poly& p, const Mat& a) {
  Mat r = identity(a.rows);
  for (int k = 1; k <= p.degree; ++k) r = r * a + p.c[k] * identity(a.rows);
  return r;
}

// Controllability matrix [Γ, ΦΓ, …, Φ^(n−1)Γ].
inline Mat controllability(const Mat& phi, const Mat& gamma) {
  const int n = phi.rows;
  Mat ctrb = zeros(n, n);
  Mat col = gamma;
  for (int k = 0; k < n; ++k) {
    place(&ctrb, col, 0, k);
    col = phi * col;
  }
  return ctrb;
}

// Feedback row L (1×n) with eig(Φ − Γ L) = roots of `want`. False if (Φ, Γ) is not controllable.
inline bool ackermann(const Mat& phi, const Mat& gamma, const Poly& want, Mat* l) {
  const int n = phi.rows;
  Mat en = zeros(n, 1);
  en(n - 1, 0) = 1.0;
  Mat y;  // 𝒞ᵀ y = e_n  ⇒  yᵀ = e_nᵀ 𝒞⁻¹
  if (!solve(transpose(controllability(phi, gamma)), en, &y, 1e-18)) return false;
  *l = transpose(y) * poly_of_matrix(want, phi);
  return true;
}

// Continuous pole s (1/s) to the discrete pole e^{s·Ts}.
inline Cplx z_of_s(Cplx s, double ts_s) {
  double mag = 1.0;  // e^{re·Ts} by repeated squaring of a small-argument Taylor series
  {
    double x = s.re * ts_s;
    int halvings = 0;
    while ((x > 0.5 || x < -0.5) && halvings < 60) {
      x *= 0.5;
      ++halvings;
    }
    double term = 1, sum = 1;
    for (int k = 1; k < 20; ++k) {
      term *= x / k;
      sum += term;
    }
    for (int i = 0; i < halvings; ++i) sum *= sum;
    mag = sum;
  }
  double th = s.im * ts_s, c = 1, sn = 0;  // cos/sin by Taylor after range halving
  {
    int halvings = 0;
    while ((th > 0.0625 || th < -0.0625) && halvings < 60) {
      th *= 0.5;
      ++halvings;
    }
    double t2 = th * th;
    c = 1 - t2 / 2 + t2 * t2 / 24 - t2 * t2 * t2 / 720 + t2 * t2 * t2 * t2 / 40320;
    sn = th * (1 - t2 / 6 + t2 * t2 / 120 - t2 * t2 * t2 / 5040 + t2 * t2 * t2 * t2 / 362880);
    for (int i = 0; i < halvings; ++i) {  // double-angle
      const double c2 = c * c - sn * sn, s2 = 2 * sn * c;
      c = c2;
      sn = s2;
    }
  }
  return {mag * c, mag * sn};
}

}  // namespace design
