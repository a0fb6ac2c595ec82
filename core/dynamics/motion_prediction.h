// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// The dual-quaternion blend of bone motions that carries the tissue (tissue_lattice.h).
///
/// Bone motions are rigid transforms T_b relative to rest, expressed in the muscle
/// frame M: a point fixed to bone b at p (rest, M) is at T_b p now (M). A point p with blend
/// weights w (B, Σ w = 1) moves by the dual-quaternion blend of the T_b
/// (Kavan et al. 2008, "Geometric skinning with approximate dual quaternion
/// blending"): q̂ = Σ_b w_b σ_b q̂_b / ‖Σ_b w_b σ_b q̂_b‖, with σ_b = ±1 chosen so the
/// real parts lie in the hemisphere of the bone of largest weight (shortest path).
/// Unlike the linear blend Σ w_b T_b p, it is a rigid motion at every point, so
/// it does not collapse volume between bones turning by large angles (80° flexion).
/// One T for all bones moves every point by exactly T (up to rounding).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

namespace rbfmuscle {

/// Unit dual quaternion of a rigid transform: real = rotation q, dual = ½ t q.
struct DualQuaternion {
  Eigen::Quaterniond real = Eigen::Quaterniond::Identity();  ///< rotation part
  Eigen::Quaterniond dual = Eigen::Quaterniond(0, 0, 0, 0);  ///< ½ t ⊗ real (mm)
};

/// The dual quaternion of an isometry (rotation must be orthonormal).
DualQuaternion toDualQuaternion(const Eigen::Isometry3d& transform);

/// The isometry of a unit dual quaternion: rotation of `real`, t = 2 dual ⊗ real*.
Eigen::Isometry3d toIsometry(const DualQuaternion& dq);

/// The point p (mm) moved by the dual-quaternion blend of `transforms` with the B weights at
/// `weights` (≥ 0, positive sum; unchecked: the hot loop of every carried point).
Eigen::Vector3d applyBlend(const double* weights, const std::vector<DualQuaternion>& transforms,
                           const Eigen::Vector3d& p_mm);

/// The point p (mm) moved by the linear blend Σ_b w_b T_b p / Σ_b w_b of the bone motions: the
/// point between its places on the bones, on their chord (the taut map, tissue_lattice.h).
Eigen::Vector3d applyLinearBlend(const double* weights, const std::vector<Eigen::Isometry3d>& motions,
                                 const Eigen::Vector3d& p_mm);

}  // namespace rbfmuscle
