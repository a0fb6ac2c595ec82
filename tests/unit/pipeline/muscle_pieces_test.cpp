// SPDX-License-Identifier: Apache-2.0
// countMusclePieces against shapes whose pieces are known, where the surface extractIsoSurface
// draws on the same grid splits them.
#include "pipeline/muscle_pieces.h"

#include "../dynamics/dynamics_test_shapes.h"
#include "collision/bone_distance_grid.h"
#include "geometry/iso_surface.h"
#include "geometry/mesh_measures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <stdexcept>

namespace rbfmuscle {
namespace {

/// Spheres of radius 10 mm (one kernel each, as makeSphereField) at the given centres.
GaussianField makeSpheres(const Eigen::Matrix3Xd& centres_mm) {
  const Eigen::Index n = centres_mm.cols();
  return GaussianField(-5.0, centres_mm, Eigen::VectorXd::Constant(n, 5.0 * std::exp(1.0)), Eigen::VectorXd::Constant(n, 0.01));
}

/// The positive-volume pieces of the surface extractIsoSurface draws of the state's muscle over `box`.
int countSurfacePieces(const MuscleState& state, const Eigen::AlignedBox3d& box, double cell_mm) {
  const MuscleShape shape(state);
  const TriangleMesh surface = extractIsoSurface(
      [&](const Eigen::Matrix3Xd& points, Eigen::VectorXd& out) {
        out.resize(points.cols());
        for (Eigen::Index j = 0; j < points.cols(); ++j) out[j] = shape.calcValue(points.col(j));
      },
      box, cell_mm);
  int pieces = 0;
  for (double volume : calcComponentVolumes(surface)) pieces += volume > 0.0;
  return pieces;
}

TEST(MusclePieces, OneSphereIsOnePieceOfItsVolume) {
  const MuscleState state(test::makeSphereField(), 1e-3);
  const MusclePieces p = countMusclePieces(state, 0.5);
  EXPECT_EQ(p.pieces, 1);
  EXPECT_NEAR(p.largest_volume_mm3, 4.0 / 3.0 * M_PI * 1000.0, 0.03 * 4189.0);
  EXPECT_EQ(p.stray_volume_mm3, 0.0);
  EXPECT_TRUE(p.stray_centre_mm.array().isNaN().all());  // nowhere apart
}

TEST(MusclePieces, TwoSpheresApartAreTwoPiecesAndOverlappingOnesOne) {
  Eigen::Matrix3Xd apart(3, 2), overlapping(3, 2);
  apart << 0, 30, 0, 0, 0, 0;
  overlapping << 0, 15, 0, 0, 0, 0;
  const MusclePieces two = countMusclePieces(MuscleState(makeSpheres(apart), 1e-3), 0.5);
  EXPECT_EQ(two.pieces, 2);
  EXPECT_NEAR(two.stray_volume_mm3, two.largest_volume_mm3, 0.01 * two.largest_volume_mm3);  // equal spheres
  EXPECT_EQ(countMusclePieces(MuscleState(makeSpheres(overlapping), 1e-3), 0.5).pieces, 1);
}

TEST(MusclePieces, ABoneAcrossTheRodCutsItInTwo) {
  MuscleState state(test::makeRodField(), 1e-3);
  EXPECT_EQ(countMusclePieces(state, 1.0).pieces, 1);
  const auto slab = std::make_shared<BoneDistanceGrid>(test::makeBox(Eigen::Vector3d(-3, -30, -30), Eigen::Vector3d(3, 30, 30)));
  BoneClearance bones({ClearanceBone{"slab", slab}});
  bones.setPoses({Eigen::Isometry3d::Identity()}, Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-60), Eigen::Vector3d::Constant(60)));
  state.bones = &bones;
  const MusclePieces cut = countMusclePieces(state, 1.0);
  EXPECT_EQ(cut.pieces, 2);
  EXPECT_GT(cut.stray_volume_mm3, 0.3 * cut.largest_volume_mm3);  // two halves of a rod
  EXPECT_GT(std::abs(cut.stray_centre_mm.x()), 10.0)
      << "the stray half lies beside the slab: " << cut.stray_centre_mm.transpose();
  EXPECT_LT(cut.stray_centre_mm.tail<2>().norm(), 3.0) << "on the rod's axis";
}

/// The box countMusclePieces samples: the positive kernels' cut-off boxes.
Eigen::AlignedBox3d findSampledBox(const MuscleState& state) {
  Eigen::AlignedBox3d box;
  for (int k = 0; k < state.field.getNumKernels(); ++k) {
    box.extend(state.field.getCentres().col(k) - state.field.calcHalfExtents(k));
    box.extend(state.field.getCentres().col(k) + state.field.calcHalfExtents(k));
  }
  return box;
}

TEST(MusclePieces, AMuscleWhollyInABoneIsNoPiece) {
  MuscleState state(test::makeSphereField(), 1e-3);
  const auto block = std::make_shared<BoneDistanceGrid>(test::makeBox(Eigen::Vector3d::Constant(-30), Eigen::Vector3d::Constant(30)));
  BoneClearance bones({ClearanceBone{"block", block}});
  bones.setPoses({Eigen::Isometry3d::Identity()}, Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-60), Eigen::Vector3d::Constant(60)));
  state.bones = &bones;
  const MusclePieces none = countMusclePieces(state, 1.0);
  EXPECT_EQ(none.pieces, 0);
  EXPECT_EQ(none.largest_volume_mm3, 0.0);
  EXPECT_EQ(none.stray_volume_mm3, 0.0);
}

TEST(MusclePieces, CountsTheSpheresThatTouchAsOnePieceWhateverTheCell) {
  // Two kernels of makeSpheres join where they are under 26.0 mm apart (f = 0 midway). Of these
  // five, 0–1 (25.6 mm), 1–4 (25.9 mm, a neck about 2.3 mm across) and 3–4 (25.2 mm) join, and
  // 2 is 26.2 mm from 1: two pieces.
  Eigen::Matrix3Xd centres(3, 5);
  centres << 0, 25.6, 51.8, 0, 25.2, 0, 0.4, 0, 26.1, 26.3, 0, 0.2, 0.5, 0, 1.1;
  const MuscleState state(makeSpheres(centres), 1e-3);
  for (double cell_mm : {0.7, 1.0, 1.5, 2.0, 3.0}) {
    const MusclePieces p = countMusclePieces(state, cell_mm);
    EXPECT_EQ(p.pieces, 2) << cell_mm << " mm";
    // Where the muscle comes apart: the lone sphere 2.
    EXPECT_LT((p.stray_centre_mm - centres.col(2)).norm(), 0.5) << cell_mm << " mm: " << p.stray_centre_mm.transpose();
  }
}

TEST(MusclePieces, JoinsANeckThinnerThanTheCellWhereTheSurfaceOnTheSameGridSplits) {
  // 25.98 mm apart: a neck about 1.5 mm across, which a grid of cells larger than it may step
  // over, depending on where its nodes fall.
  Eigen::Matrix3Xd centres(3, 2);
  centres << 0, 25.98, 0, 0.3, 0, 0.7;
  const MuscleState state(makeSpheres(centres), 1e-3);
  int cells_where_the_surface_splits = 0;
  for (double cell_mm : {1.5, 2.0, 2.5, 3.0, 3.5}) {
    EXPECT_EQ(countMusclePieces(state, cell_mm).pieces, 1) << cell_mm << " mm";
    cells_where_the_surface_splits += countSurfacePieces(state, findSampledBox(state), cell_mm) > 1;
  }
  EXPECT_GT(cells_where_the_surface_splits, 0);
}

TEST(MusclePieces, RefusesABadCellAndAnUnboundedField) {
  const MuscleState state(test::makeSphereField(), 1e-3);
  EXPECT_THROW(countMusclePieces(state, 0.0), std::invalid_argument);
  const GaussianField inverted(5.0, Eigen::Matrix3Xd::Zero(3, 1), Eigen::VectorXd::Constant(1, -1.0), Eigen::VectorXd::Constant(1, 0.01));
  try {
    countMusclePieces(MuscleState(inverted, 1e-3), 1.0);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("not bounded"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rbfmuscle
