// SPDX-License-Identifier: Apache-2.0
#include "geometry/mesh_measures.h"

#include <gtest/gtest.h>

#include <cmath>

#include "geometry/mesh_io.h"
#include "unit/geometry/test_meshes.h"

namespace rbfmuscle {
namespace {

using test::modelPath;

TEST(MeshMeasures, BoxVolumeAndArea) {
  // models/shapes/box.ply: 100 × 80 × 100 mm.
  const TriangleMesh box = loadMesh(modelPath("shapes/box.ply"));
  EXPECT_NEAR(calcVolume(box), 100.0 * 80.0 * 100.0, 1e-6 * 8e5);
  EXPECT_NEAR(calcArea(box), 2 * (100.0 * 80.0 + 100.0 * 100.0 + 80.0 * 100.0), 1e-6 * 5.6e4);
  EXPECT_EQ(countComponents(box), 1);
}

TEST(MeshMeasures, EachPieceIsAsFarAcrossAsItsBoundingBoxsDiagonal) {
  // The box (100 × 80 × 100 mm) and a triangle 1 mm across beside it, apart from it.
  TriangleMesh mesh = loadMesh(modelPath("shapes/box.ply"));
  const int v = mesh.countVertices();
  mesh.vertices_mm.conservativeResize(3, v + 3);
  mesh.vertices_mm.rightCols(3) << 500, 501, 500,  //
                                   0, 0, 0,        //
                                   0, 0, 0.5;
  mesh.triangles.conservativeResize(3, mesh.countTriangles() + 1);
  mesh.triangles.rightCols(1) << v, v + 1, v + 2;
  const std::vector<double> sizes = calcComponentSizes(mesh);
  ASSERT_EQ(sizes.size(), 2u);
  EXPECT_NEAR(sizes[0], std::sqrt(100.0 * 100.0 + 80.0 * 80.0 + 100.0 * 100.0), 1e-9);
  EXPECT_NEAR(sizes[1], std::sqrt(1.0 + 0.25), 1e-12);
}

TEST(MeshMeasures, GluteusMaximusVolume) {
  const TriangleMesh m = loadMesh(modelPath("hip/meshes/gluteus_maximus_r.ply"));
  EXPECT_NEAR(calcVolume(m), 746.6e3, 0.005 * 746.6e3);  // 746.6 ml
}

TEST(MeshMeasures, VolumeIsUnchangedByRigidMotionAndFlipsWithWinding) {
  const TriangleMesh m = loadMesh(modelPath("hip/meshes/iliacus_r.ply"));
  const double v = calcVolume(m);
  TriangleMesh moved = m;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  moved.vertices_mm = (R * m.vertices_mm).colwise() + Eigen::Vector3d(500, -300, 800);
  EXPECT_NEAR(calcVolume(moved), v, 1e-9 * v);
  EXPECT_NEAR(calcArea(moved), calcArea(m), 1e-9 * calcArea(m));
  moved.triangles.row(1).swap(moved.triangles.row(2));
  EXPECT_NEAR(calcVolume(moved), -v, 1e-9 * v);
}

TEST(MeshMeasures, TetrahedronAndIcosphere) {
  TriangleMesh tet;
  tet.vertices_mm.resize(3, 4);
  tet.vertices_mm << 0, 3, 0, 0, 0, 0, 4, 0, 0, 0, 0, 5;
  tet.triangles.resize(3, 4);
  tet.triangles << 0, 0, 0, 1, 2, 1, 3, 2, 1, 3, 2, 3;
  EXPECT_NEAR(calcVolume(tet), 3.0 * 4.0 * 5.0 / 6.0, 1e-12);
  const TriangleMesh sphere = test::makeIcosphere(10.0, 4);
  const double exact = 4.0 / 3.0 * M_PI * 1000.0;
  EXPECT_NEAR(calcVolume(sphere), exact, 0.01 * exact);
  EXPECT_LT(calcVolume(sphere), exact);  // inscribed polyhedron
  EXPECT_NEAR(calcArea(sphere), 4.0 * M_PI * 100.0, 0.01 * 4.0 * M_PI * 100.0);
}

}  // namespace
}  // namespace rbfmuscle
