// SPDX-License-Identifier: Apache-2.0
#pragma once
/// Shared matrix comparison for every test suite: one place decides what
/// "equal within tolerance" means and prints both operands on failure.
#include <Eigen/Core>
#include <gtest/gtest.h>
#include <sstream>

namespace rbfmuscle::test {

/// Passes when max|a-b| <= abs_tol + rel_tol * max(|a|max, |b|max).
template <typename A, typename B>
::testing::AssertionResult isApprox(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b,
                                    double rel_tol, double abs_tol = 0.0) {
  if (a.rows() != b.rows() || a.cols() != b.cols())
    return ::testing::AssertionFailure() << "shape " << a.rows() << "x" << a.cols() << " vs "
                                         << b.rows() << "x" << b.cols();
  const double scale = std::max(a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff());
  const double err = (a - b).cwiseAbs().maxCoeff();
  if (!(err <= abs_tol + rel_tol * scale)) {
    std::ostringstream s;
    s << "max abs difference " << err << " > " << abs_tol << " + " << rel_tol << " * " << scale
      << "\n a =\n" << a << "\n b =\n" << b;
    return ::testing::AssertionFailure() << s.str();
  }
  return ::testing::AssertionSuccess();
}

}  // namespace rbfmuscle::test
