// Just enough dense linear algebra for the plant models (at most ~6×6): products, a linear
// solve, and the matrix exponential for exact zero-order-hold discretisation. Double precision.
#pragma once

#include <cmath>
#include <cstddef>
#include <initializer_list>
#include <stdexcept>
#include <vector>

namespace sim {

class Matrix {
 public:
  Matrix() = default;
  Matrix(std::size_t rows, std::size_t cols) : rows_(rows), cols_(cols), a_(rows * cols, 0.0) {}
  // Row-major literal: Matrix{{1, 2}, {3, 4}}.
  Matrix(std::initializer_list<std::initializer_list<double>> rows);
  static Matrix identity(std::size_t n);
  static Matrix column(std::initializer_list<double> values);

  std::size_t rows() const { return rows_; }
  std::size_t cols() const { return cols_; }
  double& operator()(std::size_t r, std::size_t c) { return a_[r * cols_ + c]; }
  double operator()(std::size_t r, std::size_t c) const { return a_[r * cols_ + c]; }

  Matrix operator*(const Matrix& b) const;
  Matrix operator+(const Matrix& b) const;
  Matrix operator-(const Matrix& b) const;
  Matrix operator*(double s) const;
  // Max absolute row sum (the ∞-norm), used to choose the scaling in expm().
  double norm_inf() const;
  // Sub-block [r0, r0+rows) × [c0, c0+cols).
  Matrix block(std::size_t r0, std::size_t c0, std::size_t rows, std::size_t cols) const;

 private:
  std::size_t rows_ = 0, cols_ = 0;
  std::vector<double> a_;
};

// Solves A·X = B by Gaussian elimination with partial pivoting (throws if A is singular).
Matrix solve(Matrix a, Matrix b);
// e^A by scaling and squaring with a degree-12 Taylor series (ample for ‖A‖ ≤ 0.5 in double).
Matrix expm(const Matrix& a);

// Exact zero-order-hold discretisation of x' = A·x + B·u over dt: x⁺ = Φ·x + Γ·u, taken from
// exp([[A, B], [0, 0]]·dt) (Van Loan's block method).
struct Discretised {
  Matrix phi;
  Matrix gamma;
};
Discretised discretise_zoh(const Matrix& a, const Matrix& b, double dt_s);

}  // namespace sim
