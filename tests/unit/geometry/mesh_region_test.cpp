#include "geometry/mesh_region.h"

#include <gtest/gtest.h>

#include "geometry/mesh_io.h"
#include "geometry/mesh_measures.h"
#include "unit/geometry/test_meshes.h"

namespace rbfmuscle {
namespace {

using test::modelPath;

double distanceToPoints(const Eigen::Vector3d& x, const Eigen::Matrix3Xd& points) {
  return (points.colwise() - x).colwise().norm().minCoeff();
}

// The pelvis proxy near the iliacus origin landmark (CT mm), as the hip scenes' support region.
TEST(MeshRegion, KeepsExactlyTheTrianglesWithEveryCornerNearAPoint) {
  const TriangleMesh pelvis = loadMesh(modelPath("hip/meshes/pelvis_r_proxy.ply"));
  Eigen::Matrix3Xd points(3, 2);
  points << 138.474, 124.427, 235.451, 265.109, -324.078, -493.253;
  const double radius = 80.0;
  const TriangleMesh part = keepTrianglesNear(pelvis, points, radius);
  ASSERT_GT(part.countTriangles(), 0);
  ASSERT_LT(part.countTriangles(), pelvis.countTriangles());
  // Kept triangles, in order, are exactly the ones whose corners are all within the radius.
  int j = 0;
  for (int t = 0; t < pelvis.countTriangles(); ++t) {
    bool near = true;
    for (int c = 0; c < 3; ++c) near = near && distanceToPoints(pelvis.getCorner(t, c), points) <= radius;
    if (!near) continue;
    ASSERT_LT(j, part.countTriangles());
    for (int c = 0; c < 3; ++c) EXPECT_EQ(part.getCorner(j, c), pelvis.getCorner(t, c)) << t;
    ++j;
  }
  EXPECT_EQ(j, part.countTriangles());
  // Only used vertices are kept.
  std::vector<bool> used(static_cast<size_t>(part.countVertices()), false);
  for (int t = 0; t < part.countTriangles(); ++t)
    for (int c = 0; c < 3; ++c) used[static_cast<size_t>(part.triangles(c, t))] = true;
  for (bool u : used) EXPECT_TRUE(u);
  EXPECT_LT(calcArea(part), calcArea(pelvis));
}

TEST(MeshRegion, NoPointKeepsNothingAndAFarReachKeepsAll) {
  const TriangleMesh box = loadMesh(modelPath("shapes/box.ply"));
  EXPECT_EQ(keepTrianglesNear(box, Eigen::Matrix3Xd(3, 0), 1e9).countTriangles(), 0);
  const Eigen::Vector3d centre = box.calcBoundingBox().center();
  const TriangleMesh all = keepTrianglesNear(box, centre, 1e9);
  EXPECT_EQ(all.triangles, box.triangles);
  EXPECT_EQ(all.vertices_mm, box.vertices_mm);
  // Every corner of the box is farther from its centre than half its shortest side.
  EXPECT_EQ(keepTrianglesNear(box, centre, 30.0).countTriangles(), 0);
}

}  // namespace
}  // namespace rbfmuscle
