// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// The centre of the joint between two bodies, from the skeleton's own kinematics.
///
/// Turning each rotational coordinate by ±δ from the rest pose moves body B relative to
/// body A by a rigid motion M_k (in A's frame). The joint centre is the point c of A that
/// every M_k leaves in place, found by least squares over the probes: Σ_k |(R_k − I)c + t_k|²
/// (a ball joint, or three hinges whose axes meet, fixes c; a single hinge fixes its axis, and
/// c is the point of the axis nearest `near_G_mm`). A joint that also slides, or hinges whose
/// axes do not meet, leaves no point in place: the largest move of c over the probes says how
/// far from a centre the joint is.
#include "model/skeleton.h"

#include <Eigen/Core>

#include <optional>

namespace rbfmuscle {

/// What findJointCentre found.
struct JointCentre {
  Eigen::Vector3d p_G_mm = Eigen::Vector3d::Zero();  ///< the centre at the rest pose (ground, mm)
  double residual_mm = 0.0;  ///< largest move of the centre relative to body A over the probes (mm)
  int coordinates = 0;       ///< rotational coordinates that turn B relative to A
};

/// The centre of the joint (or chain of joints) between bodies A and B of `skeleton` at its rest
/// pose (file comment). The skeleton is read again from its file, so `skeleton` does not move.
/// @param near_G_mm where to pick c along a single hinge's axis (e.g. the muscle's centroid)
/// @returns no value when no rotational coordinate turns B relative to A.
/// @throws std::invalid_argument for a body index out of range.
std::optional<JointCentre> findJointCentre(const Skeleton& skeleton, int body_a, int body_b,
                                           const Eigen::Vector3d& near_G_mm);

}  // namespace rbfmuscle
