// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Via-point line-of-action paths (as OpenSim's GeometryPath without wrapping):
/// points fixed to bones, length = Σ ‖T_{b(k+1)} p_{k+1} − T_{b(k)} p_k‖.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace rbfmuscle {

/// A point on the path only while a coordinate lies in [min, max] (OpenSim's ConditionalPathPoint).
struct PathPointCondition {
  int coordinate = -1;  ///< index into the frame's coordinates; -1: always on the path
  double min = 0.0;     ///< rad or mm
  double max = 0.0;
};

/// A path of K ≥ 2 points, each fixed to one bone.
struct ViaPointPath {
  Eigen::Matrix3Xd points_mm;                  ///< 3×K rest positions (mm, M)
  std::vector<int> bones;                      ///< bone of each point, in [0, B)
  std::vector<PathPointCondition> conditions;  ///< empty (every point always on), or one per point
};

/// The path through `points_mm` (3×K, K ≥ 2, rest, M): the first point on `first_bone`, the
/// last on `last_bone`, and the intermediate points by arc length: those before half the
/// path's rest length on first_bone, the others on last_bone. This is a default only; where a
/// path bends over a bone, its points must name their bodies (splitViaPointBodies).
/// @throws std::invalid_argument if K < 2, a point is not finite or a bone index is negative.
ViaPointPath makeViaPointPath(const Eigen::Matrix3Xd& points_mm, int first_bone, int last_bone);

/// A via-point path written as text: the points, and the body each one is fixed to.
struct ViaPointText {
  std::string points;               ///< the points alone, "x y z; …" (for parseAttachmentAreaSpec)
  std::vector<std::string> bodies;  ///< body of each point; empty when the text names none
};

/// Splits a path written "x y z @ BODY; x y z @ BODY; …" into its points and bodies. A text
/// without '@' is returned whole, with no bodies. Bodies are needed wherever the path bends
/// over a bone: a via point where a muscle wraps over the pelvis can lie nearer the femur
/// than the pelvis, and halfway along the path is no rule for it either.
/// @throws std::invalid_argument naming the 1-based point when some points name a body and
///   others do not, or a body name is empty or has white space inside.
ViaPointText splitViaPointBodies(const std::string& text);

/// Length (mm) of the path through its points that are on it at coordinates `q` (rad or mm),
/// each moved by its bone's transform (bone_motion_M[b]: rest → now, M).
/// @throws std::invalid_argument if a point's bone has no transform, `conditions` is neither
///   empty nor one per point, or a condition's coordinate is outside `q`.
double calcPathLength(const ViaPointPath& path, const std::vector<Eigen::Isometry3d>& bone_motion_M,
                      const Eigen::VectorXd& q = Eigen::VectorXd());

}  // namespace rbfmuscle
