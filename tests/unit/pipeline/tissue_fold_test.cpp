// SPDX-License-Identifier: Apache-2.0
// Tissue a bone has taken, folded out of it: on a rod pressed into a slab, against a thin slab
// and tissue that does not reach the bone's face, and the gradient against finite differences.
#include "pipeline/tissue_fold.h"

#include "../dynamics/dynamics_test_shapes.h"
#include "collision/bone_distance_grid.h"
#include "pipeline/muscle_state.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

namespace rbfmuscle {
namespace {

/// A box bone at rest (identity pose), kept for the whole box ±60 mm.
BoneClearance makeBone(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  BoneClearance bones({ClearanceBone{"box", std::make_shared<BoneDistanceGrid>(test::makeBox(lo, hi))}});
  bones.setPoses({Eigen::Isometry3d::Identity()}, Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-60), Eigen::Vector3d::Constant(60)));
  return bones;
}

/// Where f = 0 on the line x = y = 0 between z = from (f > 0) and z = to (f < 0), by bisection.
double findSurfaceZ(const ImplicitField& f, double from, double to) {
  for (int i = 0; i < 60; ++i) {
    const double middle = 0.5 * (from + to);
    (f.calcValue(Eigen::Vector3d(0, 0, middle)) > 0.0 ? from : to) = middle;
  }
  return from;
}

class TissueFold : public ::testing::Test {
 protected:
  TissueFold() : state_(test::makeRodField(), 1e-3) {
    top_mm_ = findSurfaceZ(state_.field, 0.0, 20.0);
    bottom_mm_ = findSurfaceZ(state_.field, 0.0, -20.0);
  }
  MuscleState state_;
  double top_mm_ = 0.0, bottom_mm_ = 0.0;  ///< the rod's faces above and below its axis
};

TEST_F(TissueFold, ALayerPressedIntoABoneComesOutOnItsFaceAsThickAsItWentIn) {
  // The face a third of the way up: more of the rod is in the bone than out of it.
  const double face_mm = bottom_mm_ + (2.0 / 3.0) * (top_mm_ - bottom_mm_);
  const BoneClearance bone = makeBone(Eigen::Vector3d(-50, -50, -50), Eigen::Vector3d(50, 50, face_mm));
  state_.bones = &bone;
  const double out_mm = top_mm_ - face_mm, in_mm = face_mm - bottom_mm_;
  ASSERT_GT(in_mm, out_mm + 1.0);
  const MuscleShape with_fold(state_), field_alone(state_, nullptr, 0, BoneContact::kIgnored);
  // Above the rod's own top but within what went in: muscle only by the fold.
  const Eigen::Vector3d above(0, 0, face_mm + 0.5 * (out_mm + std::min(in_mm, 6.0)));
  EXPECT_LT(field_alone.calcValue(above), 0.0);
  EXPECT_GT(with_fold.calcValue(above), 0.0);
  // Beyond what went in (and the bone's band), nothing.
  EXPECT_LT(with_fold.calcValue(Eigen::Vector3d(0, 0, face_mm + in_mm + 0.5)), 0.0);
  // Inside the bone, nothing either: min(f̃, s) ≤ s < 0.
  EXPECT_LT(with_fold.calcValue(Eigen::Vector3d(0, 0, face_mm - 0.5)), 0.0);
}

TEST_F(TissueFold, NothingFoldsThroughAThinBoneNorFromTissueThatMissesTheFace) {
  // A slab 2 mm thick just above the rod: its mirror images reach through it into the rod.
  const BoneClearance thin = makeBone(Eigen::Vector3d(-50, -50, top_mm_ + 0.5), Eigen::Vector3d(50, 50, top_mm_ + 2.5));
  state_.bones = &thin;
  for (double height_mm : {1.0, 2.0, 3.0, 4.0})
    EXPECT_LE(MuscleShape(state_).calcValue(Eigen::Vector3d(0, 0, top_mm_ + 2.5 + height_mm)), 0.0) << height_mm;
  // A thick bone over the rod whose face lies 1 mm above it: the rod is inside the bone's band
  // below the face but does not reach it.
  const BoneClearance thick = makeBone(Eigen::Vector3d(-50, -50, -50), Eigen::Vector3d(50, 50, top_mm_ + 1.0));
  state_.bones = &thick;
  for (double height_mm : {0.5, 1.5, 2.5, 3.5})
    EXPECT_LE(MuscleShape(state_).calcValue(Eigen::Vector3d(0, 0, top_mm_ + 1.0 + height_mm)), 0.0) << height_mm;
}

TEST_F(TissueFold, GradientMatchesFiniteDifferences) {
  // The face 3 mm below the rod's top: above the rod, up to the bone's band, the fold wins.
  const double face_mm = top_mm_ - 3.0;
  const BoneClearance bone = makeBone(Eigen::Vector3d(-50, -50, -50), Eigen::Vector3d(50, 50, face_mm));
  const double h = 1e-5;
  int folded = 0;
  for (double x : {-7.0, 1.3, 12.0})
    for (double y : {-2.0, 0.7})
      for (double height_mm : {3.3, 3.9, 4.6, 5.4}) {
        const Eigen::Vector3d p(x, y, face_mm + height_mm);
        const auto fold = [&](const Eigen::Vector3d& q) {
          return foldOutOfBones(state_.field, bone, q, state_.field.calcSample(q));
        };
        const FieldSample at = fold(p);
        if (at.value == state_.field.calcValue(p)) continue;  // the field itself, not a fold
        ++folded;
        for (int axis = 0; axis < 3; ++axis) {
          const Eigen::Vector3d e = h * Eigen::Vector3d::Unit(axis);
          const double numeric = (fold(p + e).value - fold(p - e).value) / (2.0 * h);
          EXPECT_NEAR(at.gradient[axis], numeric, 1e-4 * std::max(1.0, std::abs(numeric)))
              << "at " << p.transpose() << ", axis " << axis;
        }
      }
  EXPECT_GE(folded, 12) << "points where a fold wins";
}

}  // namespace
}  // namespace rbfmuscle
