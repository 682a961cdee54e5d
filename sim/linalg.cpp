#include "sim/linalg.h"

#include <algorithm>
#include <utility>

namespace sim {

Matrix::Matrix(std::initializer_list<std::initializer_list<double>> rows)
    : rows_(rows.size()), cols_(rows.size() ? rows.begin()->size() : 0) {
  a_.reserve(rows_ * cols_);
  for (const auto& r : rows) {
    if (r.size() != cols_) throw std::invalid_argument("ragged matrix literal");
    a_.insert(a_.end(), r.begin(), r.end());
  }
}

Matrix Matrix::identity(std::size_t n) {
  Matrix m(n, n);
  for (std::size_t i = 0; i < n; ++i) m(i, i) = 1.0;
  return m;
}

Matrix Matrix::column(std::initializer_list<double> values) {
  Matrix m(values.size(), 1);
  std::size_t i = 0;
  for (double v : values) m(i++, 0) = v;
  return m;
}

Matrix Matrix::operator*(const Matrix& b) const {
  if (cols_ != b.rows_) throw std::invalid_argument("matrix product: shapes differ");
  Matrix m(rows_, b.cols_);
  for (std::size_t i = 0; i < rows_; ++i)
    for (std::size_t k = 0; k < cols_; ++k) {
      const double aik = (*this)(i, k);
      if (aik == 0.0) continue;
      for (std::size_t j = 0; j < b.cols_; ++j) m(i, j) += aik * b(k, j);
    }
  return m;
}

Matrix Matrix::operator+(const Matrix& b) const {
  if (rows_ != b.rows_ || cols_ != b.cols_) throw std::invalid_argument("matrix sum: shapes differ");
  Matrix m = *this;
  for (std::size_t i = 0; i < a_.size(); ++i) m.a_[i] += b.a_[i];
  return m;
}

Matrix Matrix::operator-(const Matrix& b) const { return *this + b * -1.0; }

Matrix Matrix::operator*(double s) const {
  Matrix m = *this;
  for (double& v : m.a_) v *= s;
  return m;
}

double Matrix::norm_inf() const {
  double best = 0.0;
  for (std::size_t i = 0; i < rows_; ++i) {
    double sum = 0.0;
    for (std::size_t j = 0; j < cols_; ++j) sum += std::fabs((*this)(i, j));
    best = std::max(best, sum);
  }
  return best;
}

Matrix Matrix::block(std::size_t r0, std::size_t c0, std::size_t rows, std::size_t cols) const {
  Matrix m(rows, cols);
  for (std::size_t i = 0; i < rows; ++i)
    for (std::size_t j = 0; j < cols; ++j) m(i, j) = (*this)(r0 + i, c0 + j);
  return m;
}

Matrix solve(Matrix a, Matrix b) {
  const std::size_t n = a.rows();
  if (a.cols() != n || b.rows() != n) throw std::invalid_argument("solve: shapes differ");
  for (std::size_t col = 0; col < n; ++col) {
    std::size_t pivot = col;
    for (std::size_t r = col + 1; r < n; ++r)
      if (std::fabs(a(r, col)) > std::fabs(a(pivot, col))) pivot = r;
    if (a(pivot, col) == 0.0) throw std::runtime_error("solve: singular matrix");
    for (std::size_t j = 0; j < n; ++j) std::swap(a(col, j), a(pivot, j));
    for (std::size_t j = 0; j < b.cols(); ++j) std::swap(b(col, j), b(pivot, j));
    for (std::size_t r = col + 1; r < n; ++r) {
      const double f = a(r, col) / a(col, col);
      if (f == 0.0) continue;
      for (std::size_t j = col; j < n; ++j) a(r, j) -= f * a(col, j);
      for (std::size_t j = 0; j < b.cols(); ++j) b(r, j) -= f * b(col, j);
    }
  }
  Matrix x(n, b.cols());
  for (std::size_t j = 0; j < b.cols(); ++j)
    for (std::size_t i = n; i-- > 0;) {
      double s = b(i, j);
      for (std::size_t k = i + 1; k < n; ++k) s -= a(i, k) * x(k, j);
      x(i, j) = s / a(i, i);
    }
  return x;
}

Matrix expm(const Matrix& a) {
  // Scale so ‖A/2^s‖ ≤ 0.5, sum the Taylor series (terms fall below 1e-17 by degree 12),
  // then square s times.
  int squarings = 0;
  const double norm = a.norm_inf();
  if (norm > 0.5) squarings = static_cast<int>(std::ceil(std::log2(norm / 0.5)));
  const Matrix scaled = a * std::ldexp(1.0, -squarings);
  const std::size_t n = a.rows();
  Matrix sum = Matrix::identity(n);
  Matrix term = Matrix::identity(n);
  for (int k = 1; k <= 12; ++k) {
    term = term * scaled * (1.0 / k);
    sum = sum + term;
  }
  for (int i = 0; i < squarings; ++i) sum = sum * sum;
  return sum;
}

Discretised discretise_zoh(const Matrix& a, const Matrix& b, double dt_s) {
  const std::size_t n = a.rows(), m = b.cols();
  Matrix augmented(n + m, n + m);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < n; ++j) augmented(i, j) = a(i, j) * dt_s;
    for (std::size_t j = 0; j < m; ++j) augmented(i, n + j) = b(i, j) * dt_s;
  }
  const Matrix e = expm(augmented);
  return Discretised{e.block(0, 0, n, n), e.block(0, n, n, m)};
}

}  // namespace sim
