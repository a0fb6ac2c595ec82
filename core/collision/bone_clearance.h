// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// A muscle's clearance from the bones: the signed distance to the nearest bone, in the
/// muscle frame, for the bones near the muscle this frame.
///
/// The muscle is kept out of the bones by composition: it is the set {min(f̃, s) > 0}, f̃ its
/// field with what the bones took folded out of them (visitFolds, pipeline/tissue_fold.h) and s
/// this clearance. Nothing is pushed and nothing is remembered between frames, so
/// no bone can tunnel through a muscle however far it moves in one frame, and a muscle lying
/// on a bone at rest (the iliacus on the iliac fossa) rests on it by design, sliding along it
/// as the field moves.
#include "collision/bone_distance_grid.h"
#include "rbf/implicit_field.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace rbfmuscle {

/// s and ∇s at one point of the muscle frame.
struct ClearanceSample {
  double value_mm = 0.0;                                ///< s (mm): > 0 outside every bone; a lower bound when !near
  Eigen::Vector3d gradient = Eigen::Vector3d::Zero();  ///< ∇s (frame M); zero when !near
  bool near = false;                                    ///< whether some bone's surface is within its band
};

/// One bone as the muscle sees it: its distance grid (shared between muscles) and name.
struct ClearanceBone {
  std::string name;
  std::shared_ptr<const BoneDistanceGrid> grid;  ///< in the bone's body frame B
};

/// Clearance from a set of bones (file comment). setPoses() is not thread-safe; sample() is.
class BoneClearance final : public ImplicitField {
 public:
  /// @throws std::invalid_argument if a grid is null.
  explicit BoneClearance(std::vector<ClearanceBone> bones);

  /// Sets every bone's pose X_MB (bone frame in the muscle frame, mm) and keeps the bones
  /// whose grid box, posed, overlaps `region_M` (the muscle's current box): the others are
  /// not sampled this frame.
  /// @throws std::invalid_argument on a wrong count or a non-finite pose.
  void setPoses(const std::vector<Eigen::Isometry3d>& X_MB, const Eigen::AlignedBox3d& region_M);

  /// s at y (M): the smallest value over the kept bones, with its gradient: the grid's
  /// interpolated signed distance within its band, the exact distance deeper inside a bone
  /// (so a point carried far into a bone still knows its way out), and +band_mm (not near)
  /// when no kept bone is near.
  ClearanceSample sample(const Eigen::Vector3d& y_M) const;

  /// Where tissue a bone has taken folds out to y (pipeline/tissue_fold.h): for each kept bone
  /// b with 0 < s_b(y) < band, calls visit(mirror, foot, normal, cap_mm, cap_gradient) with
  /// n = ∇s_b(y), the foot q = y − s_b n on the bone's face, the mirror m = y − 2 s_b n inside
  /// it, and cap = min(−s_b(m) − s_b/2, band − s_b): it falls to 0 where the mirror is no longer
  /// inside the bone (a bone thinner than 2 s_b there) and where y leaves the band, so nothing
  /// folds through a thin bone from its other side and the fold fades out continuously.
  /// Folds whose cap cannot exceed `floor_mm` are skipped.
  template <class Visit>
  void visitFolds(const Eigen::Vector3d& y_M, double floor_mm, Visit&& visit) const {
    for (int b : near_) {
      const ClearanceSample s = sampleBone(b, y_M);
      const double band = bones_[static_cast<size_t>(b)].grid->getSettings().band_mm;
      // s_b is 1-Lipschitz, so −s_b(m) ≤ s_b and the cap is at most min(s_b/2, band − s_b).
      if (!s.near || !(s.value_mm > 0.0) || !(std::min(0.5 * s.value_mm, band - s.value_mm) > floor_mm)) continue;
      const Eigen::Vector3d n = s.gradient, foot = y_M - s.value_mm * n, mirror = y_M - 2.0 * s.value_mm * n;
      const double inside_mm = -sampleBone(b, mirror).value_mm - 0.5 * s.value_mm, in_band_mm = band - s.value_mm;
      // Gradients for a flat face: s_b(m) = −s_b, so the first is s_b/2.
      if (inside_mm < in_band_mm)
        visit(mirror, foot, n, inside_mm, Eigen::Vector3d(0.5 * n));
      else
        visit(mirror, foot, n, in_band_mm, Eigen::Vector3d(-n));
    }
  }

  /// As an ImplicitField: s and ∇s where a bone is near, +∞ and 0 elsewhere.
  double calcValue(const Eigen::Vector3d& y_M) const override { return calcSample(y_M).value; }
  Eigen::Vector3d calcGradient(const Eigen::Vector3d& y_M) const override { return calcSample(y_M).gradient; }
  FieldSample calcSample(const Eigen::Vector3d& y_M) const override {
    const ClearanceSample s = sample(y_M);
    return s.near ? FieldSample{s.value_mm, s.gradient}
                  : FieldSample{std::numeric_limits<double>::infinity(), Eigen::Vector3d::Zero()};
  }

  /// Number of bones.
  int countBones() const { return static_cast<int>(bones_.size()); }
  /// Number of bones kept by the last setPoses.
  int countNearBones() const { return static_cast<int>(near_.size()); }
  /// The bones.
  const std::vector<ClearanceBone>& getBones() const { return bones_; }
  /// The current poses X_MB.
  const std::vector<Eigen::Isometry3d>& getPoses() const { return X_MB_; }

 private:
  /// s_b and ∇s_b of kept bone b alone (as sample()).
  ClearanceSample sampleBone(int b, const Eigen::Vector3d& y_M) const;

  std::vector<ClearanceBone> bones_;
  std::vector<Eigen::Isometry3d> X_MB_, X_BM_;
  std::vector<int> near_;
  double far_value_mm_ = 0.0;
};

}  // namespace rbfmuscle
