// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// What a frame's stages read and write: the frame's input and the muscle's state.
#include "collision/bone_clearance.h"
#include "geometry/triangle_mesh.h"
#include "pipeline/tissue_fold.h"
#include "rbf/deformed_field.h"
#include "rbf/implicit_field.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

namespace rbfmuscle {

/// The frame's input, in the muscle frame M (the ground frame shifted to the rest muscle's
/// box centre, mm).
struct FrameInput {
  /// Motion of the origin (0) and insertion (1) bones since rest: a rest point of bone b is
  /// at bone_motion_M[b] · p now.
  std::vector<Eigen::Isometry3d> bone_motion_M;
  /// Pose X_MB of every contact bone (empty without contacts).
  std::vector<Eigen::Isometry3d> X_MB;
  /// Whether the tracked surface is needed this frame (pictures, penetration output).
  bool want_surface = false;
};

/// The muscle this frame. Stages fill it in order; see MusclePipeline.
struct MuscleState {
  explicit MuscleState(const GaussianField& rest, double cutoff) : field(rest, cutoff) {}
  DeformedField field;                ///< f: the deformed kernels, weights with the volume correction
  Eigen::Matrix3Xd anchors_mm;        ///< kernel centres as the tissue map carried them (3×N)
  Eigen::Matrix3Xd quadrature_mm;     ///< carried quadrature points (3×M)
  Eigen::VectorXd volume_changes;     ///< J of the carried lattice at each quadrature point (M)
  Eigen::VectorXd clearance_mm;       ///< s at each quadrature point (M); +∞ far from the bones
  const BoneClearance* bones = nullptr;  ///< posed bones this frame; null without contacts
  Eigen::Matrix3Xd fibre_points_mm;   ///< current fibre points (3×N(S+1))
  Eigen::Matrix3Xd fibre_attachments_mm;  ///< current fibre attachments on the areas (3×2N, RestFibres)
  TriangleMesh surface_M;             ///< tracked surface (when wanted)
};

/// How a MuscleShape sees the bones.
enum class BoneContact {
  kIgnored,  ///< the field alone: f
  kCut,      ///< the field outside the bones: min(f, s)
  kFolded,   ///< the muscle: min(f̃, s), with what the bones took folded out of them (tissue_fold.h)
};

/// The muscle at y given f's sample there (value and gradient), as `contact` says: f;
/// min(f, s); or min(f̃, s), with what the bones took folded out of them (tissue_fold.h).
/// Gradient of the smaller one.
inline FieldSample applyBones(const MuscleState& state, const Eigen::Vector3d& y_mm, FieldSample f,
                              BoneContact contact) {
  if (!state.bones || contact == BoneContact::kIgnored) return f;
  const ClearanceSample s = state.bones->sample(y_mm);  // far from every bone: s ≥ its band, the zero set is f's
  if (contact == BoneContact::kFolded && s.near && s.value_mm > 0.0 && f.value < s.value_mm)
    f = foldOutOfBones(state.field, *state.bones, y_mm, f);
  return s.near && s.value_mm < f.value ? FieldSample{s.value_mm, s.gradient} : f;
}

/// The muscle as a set: g(y) = min(f̃(y), s(y)), inside where g > 0 — the field outside the
/// bones, with what they took folded out of them (tissue_fold.h); or, as `contact` says, f alone
/// or min(f, s). Gradient of the smaller one. With a kernel list (a carried point's rest
/// neighbours, neighbour_lists.h) f sums that list only; without one, and at the folds, the
/// field's general search.
class MuscleShape final : public ImplicitField {
 public:
  explicit MuscleShape(const MuscleState& state, const int* kernels = nullptr, int count = 0,
                       BoneContact contact = BoneContact::kFolded)
      : state_(state), kernels_(kernels), count_(count), contact_(contact) {}
  double calcValue(const Eigen::Vector3d& p_mm) const override { return calcSample(p_mm).value; }
  Eigen::Vector3d calcGradient(const Eigen::Vector3d& p_mm) const override { return calcSample(p_mm).gradient; }
  FieldSample calcSample(const Eigen::Vector3d& p_mm) const override {
    return applyBones(state_, p_mm,
                      kernels_ ? state_.field.calcSampleAmong(p_mm, kernels_, count_) : state_.field.calcSample(p_mm),
                      contact_);
  }

 private:
  const MuscleState& state_;
  const int* kernels_;
  int count_;
  BoneContact contact_;
};

}  // namespace rbfmuscle
