// SPDX-License-Identifier: Apache-2.0
#include "fit/design_matrix.h"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <random>

#include "support/eigen_compare.h"

namespace rbfmuscle {
namespace {

/// A random sparse 200×30 matrix as DesignMatrix and dense.
void makeRandomMatrix(DesignMatrix& sparse, Eigen::MatrixXd& dense) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> value(0.0, 1.0);
  dense.setZero(sparse.getNumRows(), 30);
  for (int k = 0; k < 30; ++k) {
    std::vector<int> rows;
    std::vector<double> values;
    for (int i = 0; i < sparse.getNumRows(); ++i)
      if (value(rng) < 0.3) {
        rows.push_back(i);
        values.push_back(value(rng));
        dense(i, k) = values.back();
      }
    sparse.appendColumn(rows, values);
  }
}

TEST(DesignMatrix, ProductsMatchDense) {
  DesignMatrix A(200);
  Eigen::MatrixXd D;
  makeRandomMatrix(A, D);
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(30, -1, 2), v = Eigen::VectorXd::LinSpaced(200, 3, -1);
  Eigen::VectorXd Ax, Atv;
  A.multiply(x, Ax);
  A.multiplyTransposed(v, Atv);
  EXPECT_TRUE(test::isApprox(Ax, D * x, 1e-14));
  EXPECT_TRUE(test::isApprox(Atv, D.transpose() * v, 1e-14));
  EXPECT_TRUE(test::isApprox(A.calcColumnNormsSquared(), D.colwise().squaredNorm().transpose(), 1e-14));
}

TEST(DesignMatrix, RefitSolvesTheRidgeNormalEquations) {
  DesignMatrix A(200);
  Eigen::MatrixXd D;
  makeRandomMatrix(A, D);
  const Eigen::VectorXd y = Eigen::VectorXd::LinSpaced(200, -2, 5).array().sin().matrix();
  const double mu = 1e-3;
  const Eigen::MatrixXd normal = D.transpose() * D + mu * Eigen::MatrixXd::Identity(30, 30);
  const Eigen::VectorXd expected = normal.ldlt().solve(D.transpose() * y);
  Eigen::VectorXd lambda = Eigen::VectorXd::Zero(30);
  const RefitReport report = refitWeights(A, y, mu, 500, 1e-12, lambda);
  EXPECT_TRUE(report.reached_tolerance) << report.relative_residual;
  EXPECT_TRUE(test::isApprox(lambda, expected, 1e-8));
}

TEST(DesignMatrix, RefitReportsTheIterationCap) {
  DesignMatrix A(200);
  Eigen::MatrixXd D;
  makeRandomMatrix(A, D);
  Eigen::VectorXd lambda = Eigen::VectorXd::Zero(30);
  const RefitReport report = refitWeights(A, Eigen::VectorXd::Ones(200), 1e-6, 2, 1e-14, lambda);
  EXPECT_FALSE(report.reached_tolerance);
  EXPECT_EQ(report.iterations, 2);
  EXPECT_TRUE(lambda.allFinite());
}

}  // namespace
}  // namespace rbfmuscle
