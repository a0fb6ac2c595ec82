#pragma once
/// @file
/// Prediction of the centres and of carried points from the bone motion.
///
/// Bone motions are rigid transforms T_b relative to rest, expressed in the muscle
/// frame M: a point fixed to bone b at p (rest, M) is at T_b p now (M). Attached
/// centres move exactly rigidly with their bone. Every other point p with blend
/// weights w (B, Σ w = 1) moves by the dual-quaternion blend of the T_b
/// (Kavan et al. 2008, "Geometric skinning with approximate dual quaternion
/// blending"): q̂ = Σ_b w_b σ_b q̂_b / ‖Σ_b w_b σ_b q̂_b‖, with σ_b = ±1 chosen so the
/// real parts lie in the hemisphere of the bone of largest weight (shortest path).
/// Unlike the linear blend Σ w_b T_b p, it is a rigid motion at every point, so
/// it does not collapse volume between bones turning by large angles (80° flexion).
/// One T for all bones moves every point by exactly T (up to rounding).
#include "dynamics/attachment.h"

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

/// Dual-quaternion blend of `transforms` (size B) with `weights` (B, ≥ 0, sum > 0): see file comment.
/// @throws std::invalid_argument on a size mismatch or a zero weight sum.
Eigen::Isometry3d blendTransforms(const Eigen::Ref<const Eigen::VectorXd>& weights,
                                  const std::vector<DualQuaternion>& transforms);

/// Moves every rest point (3×M) by the blend of the bone transforms with its
/// column of `weights` (B×M); `out` is resized to 3×M. Deterministic, OpenMP over points.
/// @throws std::invalid_argument on size mismatch.
void predictPoints(const Eigen::Matrix3Xd& rest_points_mm, const Eigen::MatrixXd& weights,
                   const std::vector<DualQuaternion>& transforms, Eigen::Matrix3Xd& out);

/// Predicted centres: attached centre k → T_b ξₖ exactly; free centre k → blend
/// with column k of `centre_weights` (B×N, from calcBlendWeights of the rest centres).
/// `out` is resized to 3×N.  @throws std::invalid_argument on size mismatch.
void predictCentres(const Eigen::Matrix3Xd& rest_centres_mm, const Attachments& attachments,
                    const Eigen::MatrixXd& centre_weights, const std::vector<DualQuaternion>& transforms,
                    Eigen::Matrix3Xd& out);

}  // namespace rbfmuscle
