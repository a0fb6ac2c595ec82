// SPDX-License-Identifier: Apache-2.0
#include "geometry/self_intersection.h"

#include <gtest/gtest.h>

#include "geometry/mesh_io.h"
#include "unit/geometry/test_meshes.h"

namespace rbfmuscle {
namespace {

using test::makeCube;
using test::makeIcosphere;
using test::modelPath;

/// Two meshes as one (the second's indices shifted).
TriangleMesh join(const TriangleMesh& a, const TriangleMesh& b) {
  TriangleMesh out;
  out.vertices_mm.resize(3, a.vertices_mm.cols() + b.vertices_mm.cols());
  out.vertices_mm << a.vertices_mm, b.vertices_mm;
  out.triangles.resize(3, a.triangles.cols() + b.triangles.cols());
  out.triangles << a.triangles, (b.triangles.array() + a.countVertices()).matrix();
  return out;
}

TEST(SelfIntersection, ClosedMeshesDoNotCrossThemselves) {
  EXPECT_EQ(findSelfIntersections(makeCube(10.0)).pairs, 0);
  EXPECT_EQ(findSelfIntersections(makeIcosphere(5.0, 3)).pairs, 0);
  for (const char* file : {"shapes/box.ply", "hip/meshes/gluteus_maximus_r.ply", "hip/meshes/iliacus_r.ply"})
    EXPECT_EQ(findSelfIntersections(loadMesh(modelPath(file))).pairs, 0) << file;
}

TEST(SelfIntersection, TwoSeparatePiecesDoNotCross) {
  EXPECT_EQ(findSelfIntersections(join(makeCube(10.0), makeCube(10.0, 20.0))).pairs, 0);
}

TEST(SelfIntersection, OverlappingPiecesAreFoundWithTheTrianglesNamed) {
  const SelfIntersections found = findSelfIntersections(join(makeCube(10.0), makeCube(10.0, 5.0)));
  EXPECT_GT(found.pairs, 0);
  EXPECT_FALSE(found.capped);
  ASSERT_FALSE(found.examples.empty());
  EXPECT_LT(found.examples[0].first, 12);    // one triangle of each cube
  EXPECT_GE(found.examples[0].second, 12);
}

TEST(SelfIntersection, SearchStopsAtTheCap) {
  const SelfIntersections found = findSelfIntersections(join(makeIcosphere(5.0, 3), makeIcosphere(5.0, 3)), 5);
  EXPECT_EQ(found.pairs, 5);
  EXPECT_TRUE(found.capped);
}

TEST(SelfIntersection, TriangleTestSeparatesAndCrosses) {
  const Eigen::Vector3d a0(0, 0, 0), a1(1, 0, 0), a2(0, 1, 0);
  // Crossing: a triangle standing through the first one.
  EXPECT_TRUE(trianglesIntersect(a0, a1, a2, {0.2, 0.2, -1}, {0.2, 0.2, 1}, {0.3, 0.1, 0}, 1e-12));
  // Parallel above it.
  EXPECT_FALSE(trianglesIntersect(a0, a1, a2, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, 1e-12));
  // Coplanar and apart.
  EXPECT_FALSE(trianglesIntersect(a0, a1, a2, {2, 2, 0}, {3, 2, 0}, {2, 3, 0}, 1e-12));
  // Coplanar and overlapping.
  EXPECT_TRUE(trianglesIntersect(a0, a1, a2, {0.1, 0.1, 0}, {2, 0.1, 0}, {0.1, 2, 0}, 1e-12));
}

}  // namespace
}  // namespace rbfmuscle
