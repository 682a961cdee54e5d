// Eigenvalues and eigenvectors of small real matrices, for the modal realisation of identified
// models (seed000's matrices mix time constants from 0.1 s to 1000 s; in modal form each state
// row has one or two coefficients of similar size, which is what the fixed-point runtime needs).
// Method: Householder reduction to Hessenberg form, then Francis double-shift QR (Golub & Van
// Loan, Matrix Computations, §7.5); eigenvectors by inverse iteration in complex arithmetic.
#pragma once

#include "design/matrix.h"

namespace design {

struct Cplx {
  double re = 0, im = 0;
};
inline Cplx cmul(Cplx a, Cplx b) { return {a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re}; }
inline Cplx cdiv(Cplx a, Cplx b) {
  const double d = b.re * b.re + b.im * b.im;
  return {(a.re * b.re + a.im * b.im) / d, (a.im * b.re - a.re * b.im) / d};
}
inline double cabs2(Cplx a) { return a.re * a.re + a.im * a.im; }

inline double sqrt_(double x) {  // Newton, so the header needs no <cmath> (AVR-portable)
  if (x <= 0) return 0;
  double r = x > 1 ? x : 1;
  for (int i = 0; i < 200; ++i) {
    const double next = 0.5 * (r + x / r);
    if (next >= r) break;
    r = next;
  }
  return r;
}

// One Householder reflector P = I − 2vvᵀ/(vᵀv) applied to rows r0.. of columns [c0, c1] from the
// left and to columns r0.. of rows [q0, q1] from the right (a similarity transform).
inline void reflect(Mat* h, const double* v, int len, int r0, int c0, int c1, int q0, int q1) {
  double vv = 0;
  for (int i = 0; i < len; ++i) vv += v[i] * v[i];
  if (vv == 0) return;
  for (int j = c0; j <= c1; ++j) {
    double d = 0;
    for (int i = 0; i < len; ++i) d += v[i] * (*h)(r0 + i, j);
    d *= 2 / vv;
    for (int i = 0; i < len; ++i) (*h)(r0 + i, j) -= d * v[i];
  }
  for (int i = q0; i <= q1; ++i) {
    double d = 0;
    for (int k = 0; k < len; ++k) d += v[k] * (*h)(i, r0 + k);
    d *= 2 / vv;
    for (int k = 0; k < len; ++k) (*h)(i, r0 + k) -= d * v[k];
  }
}

// Householder vector that maps x (len 2 or 3) onto a multiple of e1.
inline void house(const double* x, int len, double* v) {
  double norm = 0;
  for (int i = 0; i < len; ++i) norm += x[i] * x[i];
  norm = sqrt_(norm);
  for (int i = 0; i < len; ++i) v[i] = x[i];
  v[0] += x[0] >= 0 ? norm : -norm;
}

// All eigenvalues of a (n <= kMatCap). Returns false if QR did not converge.
inline bool eigenvalues(const Mat& a, Cplx* out) {
  const int n = a.rows;
  Mat h = a;
  for (int k = 0; k + 2 < n; ++k) {  // Hessenberg reduction
    double x[kMatCap] = {}, v[kMatCap] = {};
    const int len = n - k - 1;
    for (int i = 0; i < len; ++i) x[i] = h(k + 1 + i, k);
    house(x, len, v);
    reflect(&h, v, len, k + 1, 0, n - 1, 0, n - 1);
  }
  int hi = n - 1;
  int iter = 0;
  while (hi >= 0) {
    int l = hi;
    for (; l > 0; --l) {
      const double s = fabs_(h(l - 1, l - 1)) + fabs_(h(l, l));
      if (fabs_(h(l, l - 1)) <= 1e-15 * (s > 0 ? s : 1)) break;
    }
    if (l == hi) {
      out[hi] = {h(hi, hi), 0};
      --hi;
      iter = 0;
      continue;
    }
    if (l == hi - 1) {  // 2×2 block: closed form
      const double p = 0.5 * (h(hi - 1, hi - 1) - h(hi, hi));
      const double q = p * p + h(hi - 1, hi) * h(hi, hi - 1);
      const double m = 0.5 * (h(hi - 1, hi - 1) + h(hi, hi));
      if (q >= 0) {
        const double r = sqrt_(q);
        out[hi - 1] = {m + r, 0};
        out[hi] = {m - r, 0};
      } else {
        out[hi - 1] = {m, sqrt_(-q)};
        out[hi] = {m, -sqrt_(-q)};
      }
      hi -= 2;
      iter = 0;
      continue;
    }
    if (++iter > 60) return false;
    // Francis double shift from the trailing 2×2 (exceptional shift every 10 sweeps).
    double s = h(hi - 1, hi - 1) + h(hi, hi);
    double t = h(hi - 1, hi - 1) * h(hi, hi) - h(hi - 1, hi) * h(hi, hi - 1);
    if (iter % 10 == 0) {
      const double w = fabs_(h(hi, hi - 1)) + fabs_(h(hi - 1, hi - 2));
      s = 1.5 * w;
      t = w * w;
    }
    double x[3] = {h(l, l) * h(l, l) + h(l, l + 1) * h(l + 1, l) - s * h(l, l) + t,
                   h(l + 1, l) * (h(l, l) + h(l + 1, l + 1) - s), h(l + 1, l) * h(l + 2, l + 1)};
    for (int k = l; k + 1 < hi; ++k) {
      double v[3];
      house(x, 3, v);
      const int c0 = k > l ? k - 1 : l;
      const int q1 = k + 3 < hi ? k + 3 : hi;
      reflect(&h, v, 3, k, c0, hi, l, q1);
      x[0] = h(k + 1, k);
      x[1] = h(k + 2, k);
      if (k + 3 <= hi) x[2] = h(k + 3, k);
    }
    double v[2];
    house(x, 2, v);
    reflect(&h, v, 2, hi - 1, hi - 2, hi, l, hi);
  }
  return true;
}

// Eigenvector for eigenvalue lambda by inverse iteration on (A − λ̃I), λ̃ nudged off λ so the
// solve is finite. Complex Gaussian elimination with partial pivoting; n <= kMatCap.
inline bool eigenvector(const Mat& a, Cplx lambda, Cplx* vec) {
  const int n = a.rows;
  const double mag = sqrt_(cabs2(lambda)) + norm_inf(a) * 1e-3;
  const Cplx shift = {lambda.re + mag * 1e-9, lambda.im + mag * 1e-10};
  for (int i = 0; i < n; ++i) vec[i] = {1.0 / (i + 1), 0.3 / (i + 2)};  // generic start
  for (int it = 0; it < 3; ++it) {
    Cplx m[kMatCap][kMatCap + 1];
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) m[i][j] = {a(i, j), 0};
      m[i][i].re -= shift.re;
      m[i][i].im -= shift.im;
      m[i][n] = vec[i];
    }
    for (int c = 0; c < n; ++c) {
      int p = c;
      for (int i = c + 1; i < n; ++i)
        if (cabs2(m[i][c]) > cabs2(m[p][c])) p = i;
      if (cabs2(m[p][c]) == 0) return false;
      for (int j = 0; j <= n; ++j) {
        const Cplx t = m[c][j];
        m[c][j] = m[p][j];
        m[p][j] = t;
      }
      for (int i = c + 1; i < n; ++i) {
        const Cplx f = cdiv(m[i][c], m[c][c]);
        for (int j = c; j <= n; ++j) {
          const Cplx d = cmul(f, m[c][j]);
          m[i][j].re -= d.re;
          m[i][j].im -= d.im;
        }
      }
    }
    double norm = 0;
    for (int i = n - 1; i >= 0; --i) {
      Cplx s = m[i][n];
      for (int k = i + 1; k < n; ++k) {
        const Cplx d = cmul(m[i][k], vec[k]);
        s.re -= d.re;
        s.im -= d.im;
      }
      vec[i] = cdiv(s, m[i][i]);
      norm += cabs2(vec[i]);
    }
    norm = sqrt_(norm);
    for (int i = 0; i < n; ++i) vec[i] = {vec[i].re / norm, vec[i].im / norm};
  }
  return true;
}

}  // namespace design
