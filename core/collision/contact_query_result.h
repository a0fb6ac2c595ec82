// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Answer of one probe-point query against the bones of a BoneSet.
#include <limits>

#include <Eigen/Core>

namespace rbfmuscle {

/// Nearest-bone answer for one probe point p (world frame W, mm).
///
/// With s_b(p) the signed distance from p to the closed surface of bone b (negative inside,
/// so −s_b is the penetration depth), the reported bone is b* = argmin_b s_b(p) over the
/// bones with s_b(p) ≤ the query radius r; if there is none, `bone` = −1,
/// `signed_distance_mm` = +∞ and the points are NaN ("no bone near").
struct ContactQueryResult {
  int bone = -1;  ///< index of b* in the BoneSet, −1 when no bone is within the query radius.
  /// s_{b*}(p) (mm): negative = inside the bone by that depth; +∞ when `bone` = −1.
  double signed_distance_mm = std::numeric_limits<double>::infinity();
  /// Closest point q_W on the surface of b* (world frame, mm); NaN when `bone` = −1.
  Eigen::Vector3d closest_W = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  /// Unit outward surface normal at q_W (world frame): ∇s_{b*}(p) = sign(s)·(p − q)/‖p − q‖,
  /// or the face normal of q's triangle when p lies on the surface; so p − s·n = q, and moving
  /// p along +n by −s brings it to the surface. NaN when `bone` = −1.
  Eigen::Vector3d normal_W = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
};

}  // namespace rbfmuscle
