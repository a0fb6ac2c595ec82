// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Which Gaussian centres move rigidly with which bone, and how the free ones
/// (and any other carried point) blend the bone motions.
///
/// Bones are numbered 0 … B−1 by the caller (the same order as the transforms
/// given to the tissue lattice). Everything is in the
/// muscle frame M at rest (mm).
///
/// Centres attach by landmarks (the points of a muscle's attachment areas): a point p_M and a
/// radius r per bone; centre k attaches to the bone of the nearest landmark with ‖ξₖ − p‖ ≤ r
/// (ties: lowest landmark index).
///
/// Blend weights (of every point the tissue map carries): for a point p and a bone b with
/// attached set A_b, the distance to the set is d_b(p) = min_{k∈A_b} ‖p − ξₖ‖ (mm); the
/// weights are powers of inverse distances, w_b = (d_b + ℓ)^−p / Σ_c (d_c + ℓ)^−p, with a
/// softening length ℓ > 0 (mm) that keeps them finite on an attached centre. Bones without
/// attached centres get weight 0. Σ_b w_b = 1 up to rounding; ℓ → ∞ gives equal weights.
/// (A soft-min exp(−d_b/ℓ) put the whole change into a band of a few ℓ and split a flexed
/// muscle there; see calcBlendWeights for the power.) Given the centre of the joint between
/// the two bones, the weights can instead go by angle about it (calcJointAngleBlendWeights),
/// which cannot fold the blend within a turn that the areas' angle sets.
#include "rbf/gaussian_field.h"

#include <Eigen/Core>

#include <vector>

namespace rbfmuscle {

/// A landmark attaching nearby centres to one bone.
struct AttachmentLandmark {
  int bone = 0;                                         ///< bone index in [0, B)
  Eigen::Vector3d p_M_mm = Eigen::Vector3d::Zero();     ///< landmark in the muscle frame M at rest (mm)
  double radius_mm = 10.0;                              ///< centres within this distance attach (mm, > 0)
};

/// Attachment of every centre of one field and the rest blend weights of its centres.
struct Attachments {
  /// Number of bones B.
  int num_bones = 0;
  /// bone_of_centre[k] ∈ [0, B) for a centre attached to that bone, −1 for a free centre (size N).
  std::vector<int> bone_of_centre;
  /// Whether centre k is attached to a bone.
  bool isAttached(int k) const { return bone_of_centre[static_cast<size_t>(k)] >= 0; }
  /// Number of attached centres.
  int countAttached() const;
  /// Number of attached centres of bone b.
  int countAttachedTo(int bone) const;
};

/// Empty attachments (every centre free) for N centres and B bones.
/// @throws std::invalid_argument if N < 0 or B < 0.
Attachments makeFreeAttachments(int num_centres, int num_bones);

/// Attaches free centres of `field` by landmarks (see file comment); centres already
/// attached in `attachments` keep their bone.
/// @throws std::invalid_argument if a landmark names a bone outside [0, B), has a
///   non-finite point or a radius ≤ 0 (message names the landmark index), or
///   attachments.bone_of_centre.size() ≠ N.
void attachByLandmarks(const GaussianField& field, const std::vector<AttachmentLandmark>& landmarks,
                       Attachments& attachments);

/// Blend weights (B×M) of the points (3×M, mm, M at rest) from the attached centres
/// of `rest_centres_mm` (3×N): see file comment, with the inverse distances raised to
/// `power`, w_b ∝ (d_b + ℓ)^−p. Column j sums to 1.
/// @param length_mm softening length ℓ > 0 (mm)
/// @param power p > 0: 1 spreads a change of weight evenly between the attachments; 2 (Shepard's
///   inverse-distance weighting) keeps tissue near one attachment with its bone (the iliacus on
///   the iliac fossa took 12 % of the femur's flexion with p = 1, and was carried through the
///   thin iliac wing), at the price of a stretch gathered more towards the middle
/// @throws std::invalid_argument if no centre is attached, ℓ ≤ 0, p ≤ 0 or sizes differ.
Eigen::MatrixXd calcBlendWeights(const Eigen::Matrix3Xd& points_mm, const Eigen::Matrix3Xd& rest_centres_mm,
                                 const Attachments& attachments, double length_mm, double power = 1.0);

/// The part of each end of the angular transition where tissue turns with its bone to second
/// order (calcJointAngleBlendWeights), so tissue next to an area moves little off its bone, at
/// the cost of a fifth of the fold-free range (docs/design.md measures 0, 0.1, 0.2 and 0.3).
constexpr double kJointBlendEndFraction = 0.2;

/// Blend weights (2×M) of the points (3×M, mm, M at rest) by their angle about the centre c
/// of the joint between bone 0 and bone 1, instead of their distance: with a_b the angle at c
/// between the point and the nearest attached centre of bone b, t = a_0 / (a_0 + a_1) and
/// w_1 = h(t), w_0 = 1 − h(t), where h is the C¹ ramp that is quadratic on [0, e] and
/// [1 − e, 1] and linear between (slope 1 / (1 − e), e = `end_fraction`).
/// Why: bones turn about their joint, so the map is fold-free when a weight changes slowly
/// with the angle about c. Blending a turn θ about an axis through c turns a point by w_1 θ,
/// which scales the tissue along the turn by 1 + θ ∂w_1/∂φ; since a_0 + a_1 ≥ α, the
/// smallest angle between the two bones' attached centres seen from c, |∂w_1/∂φ| ≤
/// 1 / ((1 − e) α): no fold for turns up to (1 − e) α. (The dual-quaternion blend turns by
/// up to 4 tan(θ/4) per unit of weight rather than θ, so the exact bound is
/// calcFoldFreeTurn.) Tissue far from the joint, whose direction from c hardly changes along
/// it, stays with the bone it points at.
/// @throws std::invalid_argument if B ≠ 2, a bone has no attached centre, c is not finite,
///   e ∉ [0, 0.5) or sizes differ.
Eigen::MatrixXd calcJointAngleBlendWeights(const Eigen::Matrix3Xd& points_mm, const Eigen::Matrix3Xd& rest_centres_mm,
                                           const Attachments& attachments, const Eigen::Vector3d& joint_centre_mm,
                                           double end_fraction = kJointBlendEndFraction);

/// The weight w₁ at which calcJointAngleBlendWeights' ramp leaves its quadratic end for its
/// linear middle, h(e) (0.125 for e = 0.2): tissue with w₁ below it (or above 1 − h(e)) turns
/// with its bone to second order.
double calcJointBlendEndWeight(double end_fraction = kJointBlendEndFraction);

/// α: the smallest angle (rad) between an attached centre of bone 0 and one of bone 1, seen
/// from `joint_centre_mm` (calcFoldFreeTurn turns it into the fold-free turn).
/// @throws std::invalid_argument as calcJointAngleBlendWeights.
double calcAttachmentAngle(const Eigen::Matrix3Xd& rest_centres_mm, const Attachments& attachments,
                           const Eigen::Vector3d& joint_centre_mm);

/// The largest turn θ (rad) about an axis through the joint centre for which the weights of
/// calcJointAngleBlendWeights cannot fold the dual-quaternion blend: 4 tan(θ/4) = (1 − e) α.
double calcFoldFreeTurn(double attachment_angle_rad, double end_fraction = kJointBlendEndFraction);

}  // namespace rbfmuscle
