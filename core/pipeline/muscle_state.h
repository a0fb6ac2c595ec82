// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// What a frame's stages read and write: the frame's input and the muscle's state.
#include "collision/bone_clearance.h"
#include "geometry/triangle_mesh.h"
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
  TriangleMesh surface_M;             ///< tracked surface (when wanted)
};

/// The muscle as a set: g(y) = min(f(y), s(y)), inside where g > 0 — the field outside the
/// bones. Gradient of the smaller one. With a kernel list (a carried point's rest neighbours,
/// neighbour_lists.h) f sums that list only, so no search is built during a frame; without
/// one, the field's general search. With `with_bones` false it is the field alone.
class MuscleShape final : public ImplicitField {
 public:
  explicit MuscleShape(const MuscleState& state, const int* kernels = nullptr, int count = 0, bool with_bones = true)
      : state_(state), kernels_(kernels), count_(count), with_bones_(with_bones) {}
  double calcValue(const Eigen::Vector3d& p_mm) const override { return calcSample(p_mm).value; }
  Eigen::Vector3d calcGradient(const Eigen::Vector3d& p_mm) const override { return calcSample(p_mm).gradient; }
  FieldSample calcSample(const Eigen::Vector3d& p_mm) const override {
    const FieldSample f = kernels_ ? state_.field.calcSampleAmong(p_mm, kernels_, count_) : state_.field.calcSample(p_mm);
    if (!state_.bones || !with_bones_) return f;
    const ClearanceSample s = state_.bones->sample(p_mm);  // far from every bone: s ≥ its band, the zero set is f's
    return s.near && s.value_mm < f.value ? FieldSample{s.value_mm, s.gradient} : f;
  }

 private:
  const MuscleState& state_;
  const int* kernels_;
  int count_;
  bool with_bones_;
};

}  // namespace rbfmuscle
