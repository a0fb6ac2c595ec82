#pragma once
/// @file
/// Changing a Gaussian field's value at one point through the weights of the centres active
/// there, by the smallest weighted change: the edit shared by the topology guard and the step limit.
#include "rbf/gaussian_field.h"

#include <Eigen/Core>

#include <vector>

namespace rbfmuscle {

/// Which weights a local change may touch, and how far.
struct WeightEditLimits {
  std::vector<bool> free_mask;     ///< size N, true for free centres (changed first)
  Eigen::VectorXd max_abs_weights; ///< size N, ≥ 0: |λₖ| never goes above this
};

/// Changes f(x) by about `change` (field unit) through `weights`: the free centres active at x
/// (the attached ones only when no free one is, and `attached_too`) move by the smallest change in Σ Δλₖ²/|λₖ|
/// that changes f(x) by `change`,
///   Δλₖ = change |λₖ| φₖ(x) / Σⱼ |λⱼ| φⱼ(x)²,
/// clamped to at most |λₖ| per call, to |λₖ| ≤ its limit, and so no weight changes sign (the
/// fit's sign rule). It acts most on the centres that peak at x and little on wide ones.
/// `field` gives the centres and shapes; its own weights are not read (`weights` are).
/// @return the number of weights changed (0: none active at x, or all at a bound).
int changeValueAt(const GaussianField& field, const Eigen::Vector3d& x_mm, double change,
                  const WeightEditLimits& limits, Eigen::VectorXd& weights, ActiveCentres& scratch,
                  bool attached_too = true);

}  // namespace rbfmuscle
