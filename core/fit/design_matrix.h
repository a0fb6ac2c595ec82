// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// The sparse design matrix A of a Gaussian fit, A(i, k) = φₖ(xᵢ), stored by
/// columns so that adding a centre appends one column.
#include <Eigen/Core>

#include <vector>

namespace rbfmuscle {

/// Samples × centres matrix with one sparse column per centre.
class DesignMatrix {
 public:
  explicit DesignMatrix(int num_rows) : num_rows_(num_rows) {}

  /// Appends column k = getNumCols() with nonzeros `values` at ascending `rows`.
  void appendColumn(std::vector<int> rows, std::vector<double> values);

  /// Appends row i = getNumRows() with nonzeros `values` in columns `cols` (any order;
  /// every column keeps its rows ascending, as the new row is the last).
  void appendRow(const std::vector<int>& cols, const std::vector<double>& values);

  int getNumRows() const { return num_rows_; }
  int getNumCols() const { return static_cast<int>(columns_.size()); }
  /// Stored nonzeros in all columns.
  long long getNumNonZeros() const { return nonzeros_; }

  /// out = A x (serial scatter; identical results every run).
  void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& out) const;
  /// out = Aᵀ v (parallel over columns; each entry is one ordered dot product).
  void multiplyTransposed(const Eigen::VectorXd& v, Eigen::VectorXd& out) const;
  /// ‖A(:, k)‖² for every column k.
  Eigen::VectorXd calcColumnNormsSquared() const;

 private:
  struct Column {
    std::vector<int> rows;
    std::vector<double> values;
  };
  int num_rows_;
  long long nonzeros_ = 0;
  std::vector<Column> columns_;
};

/// How a weight refit ended.
struct RefitReport {
  int iterations = 0;
  double relative_residual = 0.0;  ///< ‖r‖/‖Aᵀy‖ of the normal equations at the end
  bool reached_tolerance = false;  ///< false: stopped by the iteration cap
};

/// Solves the ridge least-squares problem min ‖A λ − y‖² + μ‖λ‖² for λ by
/// Jacobi-preconditioned conjugate gradients on (AᵀA + μI) λ = Aᵀy, starting
/// from the λ given (warm start). Stops at ‖r‖ ≤ tolerance·‖Aᵀy‖ or after
/// `max_iterations`, and says which.
RefitReport refitWeights(const DesignMatrix& A, const Eigen::VectorXd& y, double mu,
                         int max_iterations, double tolerance, Eigen::VectorXd& lambda);

}  // namespace rbfmuscle
