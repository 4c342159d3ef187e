// Compares analytic Jacobians with central differences (as GTSAM and Sophus do) and fails the
// Catch2 test on mismatch, printing both matrices.
#pragma once

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/Core>
#include <catch2/catch.hpp>

#include "tests/support/tolerances.h"

namespace corridorsim::test {

// Central-difference Jacobian d f / d x of f: R^Cols -> R^Rows, with step
// `step * max(1, |x_i|)` in coordinate i. `f` returns anything convertible to a Rows-vector.
template <int Rows, int Cols, class F>
Eigen::Matrix<double, Rows, Cols> NumericalJacobian(F&& f, const Eigen::Matrix<double, Cols, 1>& x,
                                                    double step = kNumericalJacobianStep) {
  Eigen::Matrix<double, Rows, Cols> jacobian;
  for (int i = 0; i < Cols; ++i) {
    const double h = step * std::max(1.0, std::abs(x[i]));
    Eigen::Matrix<double, Cols, 1> x_plus = x;
    Eigen::Matrix<double, Cols, 1> x_minus = x;
    x_plus[i] += h;
    x_minus[i] -= h;
    const Eigen::Matrix<double, Rows, 1> f_plus = f(x_plus);
    const Eigen::Matrix<double, Rows, 1> f_minus = f(x_minus);
    jacobian.col(i) = (f_plus - f_minus) / (x_plus[i] - x_minus[i]);
  }
  return jacobian;
}

// REQUIREs max |analytic - numerical| <= rel_tol * max(1, max |numerical|). Add INFO(...) before
// the call to name the point being checked; it is printed with the two matrices on failure.
template <class DerivedA, class DerivedN>
void CheckJacobian(const Eigen::MatrixBase<DerivedA>& analytic,
                   const Eigen::MatrixBase<DerivedN>& numerical, double rel_tol = kJacobianRelTol) {
  REQUIRE(analytic.rows() == numerical.rows());
  REQUIRE(analytic.cols() == numerical.cols());
  const double max_error = (analytic - numerical).cwiseAbs().maxCoeff();
  const double scale = std::max(1.0, numerical.cwiseAbs().maxCoeff());
  std::ostringstream message;
  const Eigen::IOFormat format(Eigen::FullPrecision, 0, ", ", "\n", "  [", "]");
  message << "analytic Jacobian:\n"
          << analytic.format(format) << "\nnumerical Jacobian:\n"
          << numerical.format(format) << "\nmax abs error " << max_error << " > allowed "
          << rel_tol * scale;
  INFO(message.str());
  REQUIRE(max_error <= rel_tol * scale);
}

// CheckJacobian of both partial Jacobians of f(a, b) at (a, b): `d_f_d_a` against the central
// differences of f(., b) at a, then `d_f_d_b` against those of f(a, .) at b.
template <int Rows, int A, int B, class F>
void CheckPartialJacobians(F&& f, const Eigen::Matrix<double, A, 1>& a,
                           const Eigen::Matrix<double, B, 1>& b,
                           const Eigen::Matrix<double, Rows, A>& d_f_d_a,
                           const Eigen::Matrix<double, Rows, B>& d_f_d_b) {
  CheckJacobian(d_f_d_a, NumericalJacobian<Rows, A>(
                             [&](const Eigen::Matrix<double, A, 1>& x) { return f(x, b); }, a));
  CheckJacobian(d_f_d_b, NumericalJacobian<Rows, B>(
                             [&](const Eigen::Matrix<double, B, 1>& y) { return f(a, y); }, b));
}

}  // namespace corridorsim::test
