// SPDX-License-Identifier: Apache-2.0
#include "geometry/mesh_check.h"

#include <gtest/gtest.h>

#include <limits>

#include "geometry/mesh_io.h"
#include "geometry/mesh_measures.h"
#include "unit/geometry/test_meshes.h"

namespace rbfmuscle {
namespace {

using test::makeCube;
using test::modelPath;

std::string validationMessage(const TriangleMesh& mesh, const std::string& name) {
  try {
    validateMesh(mesh, name);
  } catch (const MeshError& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(MeshCheck, ShippedMeshesAreClosedOutwardSolids) {
  for (const char* file : {"shapes/box.ply", "shapes/rod.ply", "shapes/block.ply",
                           "shapes/tetrahedron.ply", "hip/meshes/femur_r.ply",
                           "hip/meshes/gluteus_maximus_r.ply", "hip/meshes/iliacus_r.ply",
                           "hip/meshes/pelvis_r_proxy.ply"}) {
    const TriangleMesh m = loadMesh(modelPath(file));
    const MeshReport r = checkMesh(m);
    EXPECT_TRUE(r.isWatertight()) << file << ": " << r.describe();
    EXPECT_TRUE(r.listProblems().empty()) << file << ": " << r.describe();
    EXPECT_EQ(r.components, 1) << file;
    EXPECT_NO_THROW(validateMesh(m, file));
  }
}

TEST(MeshCheck, OpenBoxNamesBoundaryEdgesAndFile) {
  const TriangleMesh open = test::removeTriangle(loadMesh(modelPath("shapes/box.ply")), 17);
  const MeshReport r = checkMesh(open);
  EXPECT_EQ(r.boundary_edges, 3);
  EXPECT_FALSE(r.isWatertight());
  const std::string msg = validationMessage(open, "box.ply");
  EXPECT_TRUE(contains(msg, "box.ply: 3 boundary edges")) << msg;
  EXPECT_TRUE(contains(msg, "not watertight")) << msg;
}

TEST(MeshCheck, FlippedTriangleIsInconsistentWindingWithFix) {
  TriangleMesh m = loadMesh(modelPath("shapes/box.ply"));
  std::swap(m.triangles(1, 40), m.triangles(2, 40));
  const MeshReport r = checkMesh(m);
  EXPECT_EQ(r.inconsistent_edges, 3);
  EXPECT_TRUE(r.isWatertight());
  const std::string msg = validationMessage(m, "box.ply");
  EXPECT_TRUE(contains(msg, "box.ply: 3 inconsistently wound edges")) << msg;
  EXPECT_TRUE(contains(msg, "wind them alike in a mesh tool")) << msg;
  EXPECT_TRUE(contains(msg, "`rbfmuscle fit --fix-winding` does it for a fit")) << msg;
}

TEST(MeshCheck, InwardWoundMeshIsReported) {
  TriangleMesh m = makeCube(10.0);
  m.triangles.row(1).swap(m.triangles.row(2));
  const std::string msg = validationMessage(m, "cube.stl");
  EXPECT_TRUE(contains(msg, "cube.stl: signed volume -1000 mm³")) << msg;
  EXPECT_TRUE(contains(msg, "inward")) << msg;
}

TEST(MeshCheck, DegenerateTrianglesAreCounted) {
  TriangleMesh repeated = makeCube(10.0);
  repeated.triangles(2, 3) = repeated.triangles(0, 3);
  EXPECT_EQ(checkMesh(repeated).degenerate_triangles, 1);
  EXPECT_TRUE(contains(validationMessage(repeated, "cube.obj"), "cube.obj: 1 degenerate triangles"));

  // Zero area with three distinct indices: vertex 8 is the midpoint of edge 0–1.
  TriangleMesh flat = makeCube(10.0);
  flat.vertices_mm.conservativeResize(3, 9);
  flat.vertices_mm.col(8) = (flat.vertices_mm.col(0) + flat.vertices_mm.col(1)) / 2.0;
  flat.triangles.conservativeResize(3, 13);
  flat.triangles.col(12) << 0, 8, 1;
  EXPECT_EQ(checkMesh(flat).degenerate_triangles, 1);
}

TEST(MeshCheck, NonFiniteAndNonManifoldAreCounted) {
  TriangleMesh m = makeCube(10.0);
  m.vertices_mm.conservativeResize(3, 9);
  m.vertices_mm.col(8) << 5, 5, 20;
  m.triangles.conservativeResize(3, 13);
  m.triangles.col(12) << 4, 5, 8;  // a fin on the top edge 4–5
  MeshReport r = checkMesh(m);
  EXPECT_EQ(r.non_manifold_edges, 1);
  EXPECT_EQ(r.boundary_edges, 2);
  EXPECT_TRUE(contains(validationMessage(m, "fin.ply"), "1 non-manifold edges"));
  m.vertices_mm(2, 8) = std::numeric_limits<double>::infinity();
  r = checkMesh(m);
  EXPECT_EQ(r.non_finite_vertices, 1);
  EXPECT_TRUE(contains(validationMessage(m, "fin.ply"), "fin.ply: 1 vertices with non-finite"));
}

TEST(MeshCheck, ComponentsAreCounted) {
  TriangleMesh two = makeCube(10.0);
  const TriangleMesh other = makeCube(5.0, 20.0);
  two.vertices_mm.conservativeResize(3, 16);
  two.vertices_mm.rightCols(8) = other.vertices_mm;
  two.triangles.conservativeResize(3, 24);
  two.triangles.rightCols(12) = other.triangles.array() + 8;
  EXPECT_EQ(checkMesh(two).components, 2);
  EXPECT_TRUE(checkMesh(two).listProblems().empty());
}

TEST(MeshCheck, OrientConsistentlyRepairsFlippedBox) {
  const TriangleMesh box = loadMesh(modelPath("shapes/box.ply"));
  TriangleMesh one = box;
  std::swap(one.triangles(1, 40), one.triangles(2, 40));
  EXPECT_EQ(orientConsistently(one), 1);
  EXPECT_EQ(one.triangles, box.triangles);

  TriangleMesh all = box;
  all.triangles.row(1).swap(all.triangles.row(2));
  EXPECT_EQ(orientConsistently(all), box.countTriangles());
  EXPECT_EQ(all.triangles, box.triangles);

  TriangleMesh many = box;
  for (int t = 0; t < many.countTriangles(); t += 3) std::swap(many.triangles(1, t), many.triangles(2, t));
  orientConsistently(many);
  EXPECT_TRUE(checkMesh(many).listProblems().empty()) << checkMesh(many).describe();
  EXPECT_NEAR(calcVolume(many), calcVolume(box), 1e-6);
  EXPECT_EQ(orientConsistently(many), 0);
}

TEST(MeshCheck, DescribeListsCountsAndProblems) {
  const std::string ok = checkMesh(makeCube(10.0)).describe();
  EXPECT_TRUE(contains(ok, "8 vertices, 12 triangles, 1 component")) << ok;
  EXPECT_TRUE(contains(ok, "closed")) << ok;
  const std::string open = checkMesh(test::removeTriangle(makeCube(10.0), 0)).describe();
  EXPECT_TRUE(contains(open, "3 boundary edges")) << open;
}

}  // namespace
}  // namespace rbfmuscle
