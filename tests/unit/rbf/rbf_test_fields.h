// SPDX-License-Identifier: Apache-2.0
#pragma once
/// Random Gaussian fields and finite-difference helpers shared by the rbf tests.
#include "rbf/gaussian_field.h"

#include <Eigen/Core>

#include <cmath>
#include <functional>
#include <random>

namespace rbfmuscle::test {

/// Field with n centres in a cube of half-side `half_side_mm`, weights in
/// [−2, 2] and shapes log-uniform in [alpha_min, alpha_max] (mm⁻²).
inline GaussianField makeRandomField(std::mt19937& rng, int n, double alpha_min,
                                     double alpha_max, double half_side_mm, double cutoff) {
  std::uniform_real_distribution<double> pos(-half_side_mm, half_side_mm);
  std::uniform_real_distribution<double> weight(-2.0, 2.0);
  std::uniform_real_distribution<double> log_alpha(std::log(alpha_min), std::log(alpha_max));
  Eigen::Matrix3Xd centres(3, n);
  Eigen::VectorXd weights(n), shapes(n);
  for (int k = 0; k < n; ++k) {
    centres.col(k) = Eigen::Vector3d(pos(rng), pos(rng), pos(rng));
    weights[k] = weight(rng);
    shapes[k] = std::exp(log_alpha(rng));
  }
  return GaussianField(-1.5, centres, weights, shapes, cutoff);
}

/// Central difference of a scalar function of a 3-vector: column j holds
/// (g(x + h e_j) − g(x − h e_j)) / 2h, for g returning a scalar or a vector.
inline Eigen::MatrixXd centralDifference(const std::function<Eigen::VectorXd(const Eigen::Vector3d&)>& g,
                                         const Eigen::Vector3d& x, double h) {
  Eigen::MatrixXd jac(g(x).size(), 3);
  for (int j = 0; j < 3; ++j) {
    Eigen::Vector3d plus = x, minus = x;
    plus[j] += h;
    minus[j] -= h;
    jac.col(j) = (g(plus) - g(minus)) / (2.0 * h);
  }
  return jac;
}

}  // namespace rbfmuscle::test
