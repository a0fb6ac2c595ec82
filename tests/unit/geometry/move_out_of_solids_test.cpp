// SPDX-License-Identifier: Apache-2.0
#include "geometry/move_out_of_solids.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "unit/geometry/test_meshes.h"

namespace rbfmuscle {
namespace {

using test::makeCellUnion;
using test::makeCube;

/// A box of nx × ny × nz cells of 1 mm from the origin.
TriangleMesh makeBlock(int nx, int ny, int nz) {
  std::vector<std::array<int, 3>> cells;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nz; ++k) cells.push_back({i, j, k});
  return makeCellUnion(cells);
}

/// The deepest any vertex of `mesh` lies in `solid` (mm; 0 when none is inside).
double calcDepthMax(const TriangleMesh& mesh, const MeshDistance& solid) {
  double depth = 0;
  for (int v = 0; v < mesh.countVertices(); ++v)
    depth = std::max(depth, -solid.calcSignedDistance(mesh.vertices_mm.col(v)));
  return depth;
}

/// A floor under the blocks: x, y in [−38.7, 61.3] mm, its top at z = 1.3 mm, so a block's
/// lower face lies 1.3 mm in it.
TriangleMesh makeFloor() {
  TriangleMesh floor = makeCube(100.0, -98.7);
  floor.vertices_mm.topRows(2).array() += 60.0;
  return floor;
}
const MeshDistance kFloor(makeFloor());

TEST(MoveOutOfSolids, SheetSunkIntoAFloorRisesOntoItWholeKeepingItsThickness) {
  TriangleMesh slab = makeBlock(20, 20, 2);
  const TriangleMesh before = slab;
  const MoveOutReport report = moveOutOfSolids(slab, {PlacedSolid{&kFloor, Eigen::Isometry3d::Identity(), "floor"}});
  EXPECT_EQ(report.vertices_inside, 21 * 21);  // the lower face; the middle layer is 0.3 mm deep, within the tolerance
  EXPECT_NEAR(report.depth_max_mm, 1.3, 1e-12);
  EXPECT_EQ(report.deepest_solid, "floor");
  EXPECT_EQ(report.stop, "none inside");
  EXPECT_EQ(report.rounds, 1);
  EXPECT_EQ(report.vertices_left, 0);
  EXPECT_EQ(report.vertices_moved, slab.countVertices());
  // Every vertex is within the fade of the lower face: the whole sheet moves up by 1.3 mm and
  // the clearance.
  const Eigen::Vector3d rise(0, 0, 1.3 + MoveOutSettings{}.clearance_mm);
  for (int v = 0; v < slab.countVertices(); ++v)
    EXPECT_LT((slab.vertices_mm.col(v) - before.vertices_mm.col(v) - rise).norm(), 1e-9) << v;
}

TEST(MoveOutOfSolids, MoveFadesAlongARodAndLeavesItsFarEndBitwise) {
  TriangleMesh rod = makeBlock(4, 4, 60);  // stands on the floor, 1.3 mm into it
  const TriangleMesh before = rod;
  MoveOutSettings settings;
  settings.fade_mm = 20.0;
  const MoveOutReport report = moveOutOfSolids(rod, {PlacedSolid{&kFloor, Eigen::Isometry3d::Identity(), "floor"}}, settings);
  EXPECT_EQ(report.stop, "none inside");
  EXPECT_LE(calcDepthMax(rod, kFloor), settings.tolerance_mm);
  const double lower_face_rise = 1.3 + settings.clearance_mm;
  EXPECT_NEAR(report.move_max_mm, lower_face_rise, 1e-12);
  for (int v = 0; v < rod.countVertices(); ++v)
    if (before.vertices_mm(2, v) > 20.0)
      EXPECT_TRUE((rod.vertices_mm.col(v).array() == before.vertices_mm.col(v).array()).all()) << v;
  // The rise falls along the rod (a harmonic ramp), never below 0 nor above the lower face's.
  for (int v = 0; v < rod.countVertices(); ++v) {
    const double rise = rod.vertices_mm(2, v) - before.vertices_mm(2, v);
    EXPECT_GE(rise, -1e-12);
    EXPECT_LE(rise, lower_face_rise + 1e-12);
  }
}

TEST(MoveOutOfSolids, MeshOverlappingNothingIsLeftBitwise) {
  TriangleMesh slab = makeBlock(5, 5, 2);
  slab.vertices_mm.row(2).array() += 5.0;
  const TriangleMesh before = slab;
  const MoveOutReport report = moveOutOfSolids(slab, {PlacedSolid{&kFloor, Eigen::Isometry3d::Identity(), "floor"}});
  EXPECT_EQ(report.vertices_inside, 0);
  EXPECT_EQ(report.rounds, 0);
  EXPECT_EQ(report.vertices_moved, 0);
  EXPECT_EQ(report.stop, "none inside");
  EXPECT_TRUE((slab.vertices_mm.array() == before.vertices_mm.array()).all());
}

TEST(MoveOutOfSolids, PlacedSolidIsQueriedInItsOwnFrame) {
  // The floor turned upside down about x and lifted by 2 mm: a ceiling whose face lies at
  // z = 2 − 1.3 = 0.7 mm, over y in [−61.3, 38.7], 1.3 mm into the slab from above.
  TriangleMesh slab = makeBlock(20, 20, 2);
  Eigen::Isometry3d X_mesh_solid = Eigen::Isometry3d::Identity();
  X_mesh_solid.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  X_mesh_solid.translation() = Eigen::Vector3d(0, 0, 2.0);
  const MoveOutReport report = moveOutOfSolids(slab, {PlacedSolid{&kFloor, X_mesh_solid, "ceiling"}});
  EXPECT_EQ(report.stop, "none inside");
  EXPECT_NEAR(report.depth_max_mm, 1.3, 1e-12);
  // Pushed down, not up.
  EXPECT_NEAR(slab.vertices_mm.row(2).maxCoeff(), 0.7 - MoveOutSettings{}.clearance_mm, 1e-9);
}

TEST(MoveOutOfSolids, NullSolidAndBadSettingsAreRefused) {
  TriangleMesh slab = makeBlock(2, 2, 2);
  EXPECT_THROW(moveOutOfSolids(slab, {PlacedSolid{nullptr, Eigen::Isometry3d::Identity(), "none"}}), std::invalid_argument);
  MoveOutSettings settings;
  settings.fade_mm = 0;
  EXPECT_THROW(moveOutOfSolids(slab, {}, settings), std::invalid_argument);
  settings = {};
  settings.max_rounds = 0;
  EXPECT_THROW(moveOutOfSolids(slab, {}, settings), std::invalid_argument);
  settings = {};
  settings.clearance_mm = -1;
  EXPECT_THROW(moveOutOfSolids(slab, {}, settings), std::invalid_argument);
}

}  // namespace
}  // namespace rbfmuscle
