// SPDX-License-Identifier: Apache-2.0
/// WindingNumber: 1 inside and 0 outside, the fast sum close to the exact one, and the right
/// side on the psoas major where the pseudo-normals of MeshDistance give the wrong one.
#include "geometry/winding_number.h"

#include <gtest/gtest.h>

#include <cmath>

#include "geometry/mesh_distance.h"
#include "geometry/mesh_error.h"
#include "geometry/solid_mesh.h"
#include "unit/geometry/test_meshes.h"

namespace rbfmuscle {
namespace {

using test::modelPath;

/// Evenly spread points (a lattice of n³) in the box grown by `pad_mm`.
Eigen::Matrix3Xd makeLattice(const Eigen::AlignedBox3d& box, double pad_mm, int n) {
  Eigen::Matrix3Xd p(3, n * n * n);
  const Eigen::Vector3d lo = box.min().array() - pad_mm, size = box.sizes().array() + 2 * pad_mm;
  int k = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int l = 0; l < n; ++l, ++k)
        p.col(k) = lo + size.cwiseProduct(Eigen::Vector3d(i + 0.5, j + 0.37, l + 0.61) / n);
  return p;
}

TEST(WindingNumber, IsOneInsideAndZeroOutsideACube) {
  const WindingNumber winding(test::makeCube(10.0));
  EXPECT_NEAR(winding.calcWindingNumber(Eigen::Vector3d(5, 5, 5)), 1.0, 1e-9);
  EXPECT_NEAR(winding.calcWindingNumber(Eigen::Vector3d(9.9, 0.1, 5)), 1.0, 1e-9);
  EXPECT_NEAR(winding.calcWindingNumber(Eigen::Vector3d(15, 5, 5)), 0.0, 1e-9);
  EXPECT_NEAR(winding.calcWindingNumber(Eigen::Vector3d(-40, 70, 5)), 0.0, 1e-9);
  EXPECT_TRUE(winding.isInside(Eigen::Vector3d(0.01, 5, 5)));
  EXPECT_FALSE(winding.isInside(Eigen::Vector3d(-0.01, 5, 5)));
}

TEST(WindingNumber, FastSumIsWithinAFifthOfTheExactSumOnThePsoas) {
  const WindingNumber winding(loadSolidMesh(modelPath("hip/meshes/psoas_major_r.ply")));
  const Eigen::Matrix3Xd points = makeLattice(winding.getMesh().calcBoundingBox(), 20.0, 14);
  const Eigen::VectorXd fast = winding.calcWindingNumbers(points);
  double worst = 0.0;
  for (Eigen::Index i = 0; i < points.cols(); ++i)
    worst = std::max(worst, std::abs(fast[i] - winding.calcExactWindingNumber(points.col(i))));
  EXPECT_LT(worst, WindingNumber::kAmbiguousWinding - 0.1) << "the fast sum must never flip a side";
}

TEST(WindingNumber, GivesTheRightSideWherePseudoNormalsFailOnThePsoasFolds) {
  // The psoas major has folds and slivers (two sheets back to back, umbrellas folded over)
  // whose angle-weighted pseudo-normals cancel or point inward: MeshDistance then calls
  // a whole cone of far outside points inside. The exact winding number, isInside and the
  // volume agree instead.
  const TriangleMesh mesh = loadSolidMesh(modelPath("hip/meshes/psoas_major_r.ply"));
  const WindingNumber winding(mesh);
  const MeshDistance distance(mesh);
  const Eigen::Matrix3Xd points = makeLattice(mesh.calcBoundingBox(), 20.0, 40);
  const Eigen::VectorXd s = distance.calcSignedDistances(points);
  const Eigen::Array<bool, Eigen::Dynamic, 1> inside = winding.calcInside(points);
  int wrong_far = 0, inside_count = 0;
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    inside_count += inside[i];
    if (s[i] < -10.0 && !inside[i]) {
      ++wrong_far;
      EXPECT_LT(winding.calcExactWindingNumber(points.col(i)), 0.05) << points.col(i).transpose();
    }
  }
  EXPECT_GT(wrong_far, 0) << "the psoas no longer has the folds this test is about";
  // Lattice volume of the inside against the mesh's 103.5 ml.
  const Eigen::Vector3d cell = (mesh.calcBoundingBox().sizes().array() + 40.0) / 40.0;
  EXPECT_NEAR(inside_count * cell.prod() / 1000.0, 103.5, 6.0);
}

TEST(WindingNumber, RejectsAMeshWithoutTriangles) {
  EXPECT_THROW(WindingNumber(TriangleMesh{}), MeshError);
}

}  // namespace
}  // namespace rbfmuscle
