// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// What a consumer of a muscle field needs at an arbitrary point: the value and its
/// gradient. The rest fit (GaussianField) and the moving muscle (DeformedField) provide it,
/// so fibres, surfaces and checks work with either.
#include <Eigen/Core>

namespace rbfmuscle {

/// Field value and gradient at one point.
struct FieldSample {
  double value = 0.0;                                    ///< f (field unit, ≈ mm of depth)
  Eigen::Vector3d gradient = Eigen::Vector3d::Zero();    ///< ∇f (field unit / mm)
};

/// A scalar field f over the muscle frame M (mm), positive inside the muscle.
/// Implementations are const and thread-safe for these calls.
class ImplicitField {
 public:
  virtual ~ImplicitField() = default;
  /// f(p).
  virtual double calcValue(const Eigen::Vector3d& p_mm) const = 0;
  /// ∇f(p) (field unit / mm).
  virtual Eigen::Vector3d calcGradient(const Eigen::Vector3d& p_mm) const = 0;
  /// f(p) and ∇f(p) together (implementations may share the pass).
  virtual FieldSample calcSample(const Eigen::Vector3d& p_mm) const {
    return FieldSample{calcValue(p_mm), calcGradient(p_mm)};
  }
};

}  // namespace rbfmuscle
