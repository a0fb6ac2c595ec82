// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// How far a shortened muscle's fibre lifts off the joint it winds around, as a taut string
/// lifts off a drum.
///
/// The tissue map turns the tissue between two bones about their joint, so a fibre keeps its
/// distance from the joint like a string wound on a drum, and a shortened muscle's moment arm
/// stays flat. A real shortened muscle is still taut: it leaves the joint where the straight
/// line between the places that hold it clears the joint (the iliopsoas bowstrings from the
/// pelvic brim to the lesser trochanter), and its arm grows.
///
/// Seen along the joint's turn axis, a string held at its ends lies on the boundary of the
/// convex hull of the fibre and the axis: each point's string distance s is where the ray from
/// the axis through the point leaves that hull (s ≥ its own distance r). The hull makes s
/// continuous in the points, even where the fibre winds more than half a turn or turns back.
/// A point lifts by how much further its string lies now than at rest, s − s₀, so the muscle's
/// section moves out with its string.
///
/// A fibre, taut, lies on its string: its sag, each point's distance below the string, is 0.
/// Where the map carries a shortened muscle's fibre round the joint, it sags below its string
/// further than it did at rest, and rises back out by the difference (calcSagRisesSinceRest).
/// The sag is a distance to the string, so it changes by no more than the point moves.
#include <Eigen/Core>

namespace rbfmuscle {

/// s for each 2-D point (2×m, about the origin): the distance from the origin, along the ray
/// through the point, to the boundary of the convex hull of the points and the origin. A point
/// at the origin gets 0. @throws std::invalid_argument for non-finite points.
Eigen::VectorXd calcStringDistances(const Eigen::Matrix2Xd& points);

/// The sag of each 2-D point (2×m, about the origin): its distance to its string, the boundary
/// of the convex hull of the points and the origin without the sides through the origin (0 for a
/// point on it, and for all points when the hull is degenerate).
/// @throws std::invalid_argument for non-finite points.
Eigen::VectorXd calcStringSags(const Eigen::Matrix2Xd& points);

/// The rise (3×m, mm) of each point of a fibre now (3×m) that keeps it no further below its
/// string than the same fibre at rest seen about the same axis (3×m, in the same frame as now):
/// straight away from the axis by max(0, sag − sag₀), seen along the axis (calcStringSags).
/// Near the axis, where the direction away from it changes fast with the point, the rise fades:
/// it is scaled by smoothstep(r / fade_mm), r the point's distance from the axis.
/// @throws std::invalid_argument for mismatched sizes, a non-unit axis or fade_mm ≤ 0.
Eigen::Matrix3Xd calcSagRisesSinceRest(const Eigen::Matrix3Xd& now_mm, const Eigen::Matrix3Xd& rest_mm,
                                       const Eigen::Vector3d& centre_mm, const Eigen::Vector3d& axis, double fade_mm);

/// The rise (3×m, mm) of each point of a string now (3×m), against the same string at rest
/// seen about the same axis (3×m, in the same frame as now): straight away from the axis by
/// s − s₀, never towards it. Near the axis, where the ray's direction, and so s, change fast
/// with the point, the rise fades: it is scaled by smoothstep(s₀ / fade_mm).
/// @throws std::invalid_argument for mismatched sizes, a non-unit axis or fade_mm ≤ 0.
Eigen::Matrix3Xd calcLiftOffRisesSinceRest(const Eigen::Matrix3Xd& now_mm, const Eigen::Matrix3Xd& rest_mm,
                                           const Eigen::Vector3d& centre_mm, const Eigen::Vector3d& axis,
                                           double fade_mm);

}  // namespace rbfmuscle
