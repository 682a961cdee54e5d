// Chooses the state coordinates the fixed-point runtime works in. Requirements: every state
// is a temperature-like quantity of similar size (so one Q16 °C format fits all), each row of
// the state matrix holds few coefficients of similar magnitude (one exponent per row), and the
// sensor reading is a plain sum of states (y = Σ masked x_j, no multiplies).
//  - physical models (lags in cascade, two-node) already are like that: kept;
//  - identified matrices go to real modal form: one state per real pole, a 2×2 rotation block
//    per complex pair, each mode scaled so its contribution to y is the state itself;
//  - if that fails (repeated/defective poles, unobservable mode): y becomes a state of its own.
#pragma once

#include "design/eigen.h"
#include "design/lti_model.h"

namespace design {

struct Realization {
  LtiModel model;   // transformed A, B, C (C entries 0 or 1)
  Mat to_original;  // x_original = T · x
  unsigned output_mask = 0;
  bool modal = false;
};

inline bool output_mask_of(const Mat& c, unsigned* mask) {
  *mask = 0;
  for (int j = 0; j < c.cols; ++j) {
    if (fabs_(c(0, j) - 1.0) < 1e-9)
      *mask |= 1u << j;
    else if (fabs_(c(0, j)) > 1e-9)
      return false;
  }
  return *mask != 0;
}

inline Realization transformed(const LtiModel& in, const Mat& t) {
  Realization r;
  Mat tinv;
  inverse(t, &tinv);
  r.model = in;
  r.model.a = tinv * in.a * t;
  r.model.b = tinv * in.b;
  r.model.c = in.c * t;
  r.to_original = t;
  return r;
}

// Real modal basis, slowest mode first. False if poles repeat or a mode is unobservable.
inline bool modal_basis(const LtiModel& m, Mat* t) {
  const int n = m.n;
  Cplx ev[kMatCap];
  if (!eigenvalues(m.a, ev)) return false;
  for (int i = 1; i < n; ++i)  // insertion sort by decay rate
    for (int j = i; j > 0 && fabs_(ev[j].re) < fabs_(ev[j - 1].re); --j) {
      const Cplx s = ev[j];
      ev[j] = ev[j - 1];
      ev[j - 1] = s;
    }
  double scale = 0;
  for (int i = 0; i < n; ++i) scale += sqrt_(cabs2(ev[i]));
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const Cplx d = {ev[i].re - ev[j].re, ev[i].im - ev[j].im};
      const bool conj_pair = fabs_(ev[i].re - ev[j].re) < 1e-12 * scale &&
                             fabs_(ev[i].im + ev[j].im) < 1e-12 * scale && ev[i].im != 0;
      if (!conj_pair && sqrt_(cabs2(d)) < 1e-6 * scale) return false;  // repeated pole
    }
  *t = zeros(n, n);
  for (int k = 0; k < n; ++k) {
    if (ev[k].im < 0) continue;  // the pair is built from its +im member
    Cplx v[kMatCap];
    if (!eigenvector(m.a, ev[k], v)) return false;
    if (ev[k].im == 0) {  // undo the arbitrary complex phase inverse iteration leaves
      int big = 0;
      for (int i = 1; i < n; ++i)
        if (cabs2(v[i]) > cabs2(v[big])) big = i;
      const double mag = sqrt_(cabs2(v[big]));
      const Cplx rot = {v[big].re / mag, -v[big].im / mag};
      double cv = 0;
      for (int i = 0; i < n; ++i) cv += m.c(0, i) * cmul(v[i], rot).re;
      if (fabs_(cv) < 1e-9) return false;  // mode invisible in y
      for (int i = 0; i < n; ++i) (*t)(i, k) = cmul(v[i], rot).re / cv;
    } else {
      // Basis [Re v, Im v] gives the block [[σ, ω], [−ω, σ]]; rotating it inside the plane
      // keeps the block, so turn it until the mode's output weights are (ρ, 0), then scale by 1/ρ.
      double c1 = 0, c2 = 0;
      for (int i = 0; i < n; ++i) {
        c1 += m.c(0, i) * v[i].re;
        c2 += m.c(0, i) * v[i].im;
      }
      const double rho2 = c1 * c1 + c2 * c2;
      if (rho2 < 1e-18 || k + 1 >= n) return false;
      for (int i = 0; i < n;
           ++i) {  // [vr', vi'] = [vr, vi]·[[c, −s], [s, c]] / ρ, (c,s) = (c1,c2)/ρ
        (*t)(i, k) = (v[i].re * c1 + v[i].im * c2) / rho2;
        (*t)(i, k + 1) = (-v[i].re * c2 + v[i].im * c1) / rho2;
      }
    }
  }
  return true;
}

// Fallback: replace the state with the largest output weight by y itself.
inline Mat output_state_basis(const LtiModel& m) {
  int p = 0;
  for (int j = 1; j < m.n; ++j)
    if (fabs_(m.c(0, j)) > fabs_(m.c(0, p))) p = j;
  Mat s = identity(m.n);  // x_new = S x_original
  for (int j = 0; j < m.n; ++j) s(p, j) = m.c(0, j);
  Mat t;
  inverse(s, &t);
  return t;
}

inline bool realize(const LtiModel& in, Realization* out) {
  if (in.n < 1 || in.n > kMaxModelStates) return false;
  if (in.physical_states) {
    *out = transformed(in, identity(in.n));
  } else {
    Mat t;
    const bool modal = modal_basis(in, &t);
    *out = transformed(in, modal ? t : output_state_basis(in));
    out->modal = modal;
    if (modal) {  // exact zeros off the blocks (roundoff ~1e-17 would cost runtime multiplies)
      for (int i = 0; i < in.n; ++i) {
        double big = 0;
        for (int j = 0; j < in.n; ++j)
          big = fabs_(out->model.a(i, j)) > big ? fabs_(out->model.a(i, j)) : big;
        for (int j = 0; j < in.n; ++j)
          if (fabs_(out->model.a(i, j)) < 1e-9 * big) out->model.a(i, j) = 0;
      }
      for (int j = 0; j < in.n; ++j) {
        if (fabs_(out->model.c(0, j)) < 1e-9) out->model.c(0, j) = 0;
        if (fabs_(out->model.c(0, j) - 1) < 1e-9) out->model.c(0, j) = 1;
      }
    }
  }
  return output_mask_of(out->model.c, &out->output_mask);
}

}  // namespace design
