// SPDX-License-Identifier: Apache-2.0
#include "fit/design_matrix.h"

namespace rbfmuscle {

void DesignMatrix::appendColumn(std::vector<int> rows, std::vector<double> values) {
  nonzeros_ += static_cast<long long>(rows.size());
  columns_.push_back(Column{std::move(rows), std::move(values)});
}

void DesignMatrix::appendRow(const std::vector<int>& cols, const std::vector<double>& values) {
  for (std::size_t n = 0; n < cols.size(); ++n) {
    columns_[static_cast<std::size_t>(cols[n])].rows.push_back(num_rows_);
    columns_[static_cast<std::size_t>(cols[n])].values.push_back(values[n]);
  }
  nonzeros_ += static_cast<long long>(cols.size());
  ++num_rows_;
}

void DesignMatrix::multiply(const Eigen::VectorXd& x, Eigen::VectorXd& out) const {
  out.setZero(num_rows_);
  for (int k = 0; k < getNumCols(); ++k) {
    const Column& column = columns_[k];
    const double xk = x[k];
    for (std::size_t n = 0; n < column.rows.size(); ++n) out[column.rows[n]] += column.values[n] * xk;
  }
}

void DesignMatrix::multiplyTransposed(const Eigen::VectorXd& v, Eigen::VectorXd& out) const {
  out.resize(getNumCols());
#pragma omp parallel for schedule(dynamic, 16)
  for (int k = 0; k < getNumCols(); ++k) {
    const Column& column = columns_[k];
    double sum = 0.0;
    for (std::size_t n = 0; n < column.rows.size(); ++n) sum += column.values[n] * v[column.rows[n]];
    out[k] = sum;
  }
}

Eigen::VectorXd DesignMatrix::calcColumnNormsSquared() const {
  Eigen::VectorXd norms(getNumCols());
  for (int k = 0; k < getNumCols(); ++k) {
    double sum = 0.0;
    for (double value : columns_[k].values) sum += value * value;
    norms[k] = sum;
  }
  return norms;
}

RefitReport refitWeights(const DesignMatrix& A, const Eigen::VectorXd& y, double mu,
                         int max_iterations, double tolerance, Eigen::VectorXd& lambda) {
  RefitReport report;
  const Eigen::VectorXd diagonal = (A.calcColumnNormsSquared().array() + mu).matrix();
  Eigen::VectorXd rhs, residual_rows, r, z, p, q, Ap;
  A.multiplyTransposed(y, rhs);
  const double rhs_norm = rhs.norm();
  if (rhs_norm == 0.0) {
    lambda.setZero(A.getNumCols());
    report.reached_tolerance = true;
    return report;
  }
  A.multiply(lambda, Ap);
  residual_rows = y - Ap;
  A.multiplyTransposed(residual_rows, r);
  r -= mu * lambda;
  z = r.cwiseQuotient(diagonal);
  p = z;
  double rz = r.dot(z);
  for (;;) {
    report.relative_residual = r.norm() / rhs_norm;
    if (report.relative_residual <= tolerance) {
      report.reached_tolerance = true;
      break;
    }
    if (report.iterations >= max_iterations) break;
    A.multiply(p, Ap);
    A.multiplyTransposed(Ap, q);
    q += mu * p;
    const double step = rz / p.dot(q);
    lambda += step * p;
    r -= step * q;
    z = r.cwiseQuotient(diagonal);
    const double rz_next = r.dot(z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
    ++report.iterations;
  }
  return report;
}

}  // namespace rbfmuscle
