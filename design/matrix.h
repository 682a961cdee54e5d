// Small dense matrices for the controller design math (host now, maybe the firmware's autotune
// later): fixed capacity, no heap, no STL, no exceptions — failures are reported as return values.
// Double precision; header-only so the AVR image (which globs control/*.cpp) never links it.
#pragma once

namespace design {

constexpr int kMatCap =
    8;  // model states (<= 5) + augmentations (input-delay state, bias, ZOH column)

struct Mat {
  int rows = 0;
  int cols = 0;
  double v[kMatCap][kMatCap] = {};
  double& operator()(int i, int j) { return v[i][j]; }
  double operator()(int i, int j) const { return v[i][j]; }
};

inline double fabs_(double x) { return x < 0 ? -x : x; }

inline Mat zeros(int rows, int cols) {
  Mat m;
  m.rows = rows;
  m.cols = cols;
  return m;
}

inline Mat identity(int n) {
  Mat m = zeros(n, n);
  for (int i = 0; i < n; ++i) m(i, i) = 1.0;
  return m;
}

inline Mat operator+(const Mat& a, const Mat& b) {
  Mat m = zeros(a.rows, a.cols);
  for (int i = 0; i < a.rows; ++i)
    for (int j = 0; j < a.cols; ++j) m(i, j) = a(i, j) + b(i, j);
  return m;
}

inline Mat operator-(const Mat& a, const Mat& b) {
  Mat m = zeros(a.rows, a.cols);
  for (int i = 0; i < a.rows; ++i)
    for (int j = 0; j < a.cols; ++j) m(i, j) = a(i, j) - b(i, j);
  return m;
}

inline Mat operator*(double s, const Mat& a) {
  Mat m = a;
  for (int i = 0; i < a.rows; ++i)
    for (int j = 0; j < a.cols; ++j) m(i, j) *= s;
  return m;
}

inline Mat operator*(const Mat& a, const Mat& b) {
  Mat m = zeros(a.rows, b.cols);
  for (int i = 0; i < a.rows; ++i)
    for (int j = 0; j < b.cols; ++j) {
      double s = 0;
      for (int k = 0; k < a.cols; ++k) s += a(i, k) * b(k, j);
      m(i, j) = s;
    }
  return m;
}

inline Mat transpose(const Mat& a) {
  Mat m = zeros(a.cols, a.rows);
  for (int i = 0; i < a.rows; ++i)
    for (int j = 0; j < a.cols; ++j) m(j, i) = a(i, j);
  return m;
}

// Max absolute row sum (induced infinity norm): cheap and enough to pick a scaling power.
inline double norm_inf(const Mat& a) {
  double best = 0;
  for (int i = 0; i < a.rows; ++i) {
    double s = 0;
    for (int j = 0; j < a.cols; ++j) s += fabs_(a(i, j));
    if (s > best) best = s;
  }
  return best;
}

// Solves a·x = b (b may have several columns) by Gaussian elimination with partial pivoting.
// Returns false when a pivot is below `tiny` relative to the matrix norm (singular for our use).
inline bool solve(Mat a, Mat b, Mat* x, double tiny = 1e-14) {
  const int n = a.rows;
  const double scale = norm_inf(a) > 0 ? norm_inf(a) : 1.0;
  for (int col = 0; col < n; ++col) {
    int piv = col;
    for (int i = col + 1; i < n; ++i)
      if (fabs_(a(i, col)) > fabs_(a(piv, col))) piv = i;
    if (fabs_(a(piv, col)) <= tiny * scale) return false;
    if (piv != col) {
      for (int j = 0; j < n; ++j) {
        const double t = a(col, j);
        a(col, j) = a(piv, j);
        a(piv, j) = t;
      }
      for (int j = 0; j < b.cols; ++j) {
        const double t = b(col, j);
        b(col, j) = b(piv, j);
        b(piv, j) = t;
      }
    }
    for (int i = col + 1; i < n; ++i) {
      const double f = a(i, col) / a(col, col);
      if (f == 0) continue;
      for (int j = col; j < n; ++j) a(i, j) -= f * a(col, j);
      for (int j = 0; j < b.cols; ++j) b(i, j) -= f * b(col, j);
    }
  }
  *x = zeros(n, b.cols);
  for (int i = n - 1; i >= 0; --i)
    for (int j = 0; j < b.cols; ++j) {
      double s = b(i, j);
      for (int k = i + 1; k < n; ++k) s -= a(i, k) * (*x)(k, j);
      (*x)(i, j) = s / a(i, i);
    }
  return true;
}

inline bool inverse(const Mat& a, Mat* inv) { return solve(a, identity(a.rows), inv); }

// Column j of a as an n×1 matrix, row i as 1×n: design formulas are easier to read with them.
inline Mat column(const Mat& a, int j) {
  Mat m = zeros(a.rows, 1);
  for (int i = 0; i < a.rows; ++i) m(i, 0) = a(i, j);
  return m;
}

inline Mat row(const Mat& a, int i) {
  Mat m = zeros(1, a.cols);
  for (int j = 0; j < a.cols; ++j) m(0, j) = a(i, j);
  return m;
}

// Copies `part` into `into` with its top-left corner at (r0, c0) (grows the active size).
inline void place(Mat* into, const Mat& part, int r0, int c0) {
  for (int i = 0; i < part.rows; ++i)
    for (int j = 0; j < part.cols; ++j) into->v[r0 + i][c0 + j] = part(i, j);
  if (r0 + part.rows > into->rows) into->rows = r0 + part.rows;
  if (c0 + part.cols > into->cols) into->cols = c0 + part.cols;
}

inline Mat block(const Mat& a, int r0, int c0, int rows, int cols) {
  Mat m = zeros(rows, cols);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) m(i, j) = a(r0 + i, c0 + j);
  return m;
}

inline Mat power(const Mat& a, int k) {
  Mat r = identity(a.rows);
  for (int i = 0; i < k; ++i) r = r * a;
  return r;
}

}  // namespace design
