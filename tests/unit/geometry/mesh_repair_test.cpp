// SPDX-License-Identifier: Apache-2.0
#include "geometry/mesh_repair.h"

#include <gtest/gtest.h>

#include <cmath>

#include "geometry/mesh_check.h"
#include "geometry/mesh_measures.h"
#include "unit/geometry/test_meshes.h"

namespace rbfmuscle {
namespace {

using test::appendTriangles;
using test::makeCellUnion;
using test::makeCube;

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// Expects `mesh` to bound a solid (validateMesh's checks) with one fan round every vertex:
/// repairing a copy must find nothing more to do.
void expectSolidWithoutPinches(const TriangleMesh& mesh) {
  const MeshReport report = checkMesh(mesh);
  EXPECT_TRUE(report.listProblems().empty()) << report.describe();
  TriangleMesh copy = mesh;
  const MeshRepairReport again = repairMesh(copy);
  EXPECT_FALSE(again.foundDefects()) << again.describe();
}

/// Expects the two meshes to be equal to the last bit.
void expectIdentical(const TriangleMesh& a, const TriangleMesh& b) {
  ASSERT_EQ(a.countVertices(), b.countVertices());
  ASSERT_EQ(a.countTriangles(), b.countTriangles());
  EXPECT_TRUE((a.vertices_mm.array() == b.vertices_mm.array()).all());
  EXPECT_TRUE((a.triangles.array() == b.triangles.array()).all());
}

/// `count` prisms of height 1 mm round the z axis, all sharing the edge (0,0,0)–(0,0,1): prism i
/// has the cross-section (origin, unit vector at 120°·i, unit vector at 120°·i + 60°), so
/// 2·`count` triangles meet on the shared edge.
TriangleMesh makePrismsOnOneEdge(int count) {
  std::vector<Eigen::Vector3d> points = {{0, 0, 0}, {0, 0, 1}};
  std::vector<std::array<int, 3>> faces;
  for (int i = 0; i < count; ++i) {
    const double a = 2.0 * M_PI * i / count, b = a + M_PI / 3.0;
    const int base = int(points.size());
    for (double angle : {a, b})
      for (double z : {0.0, 1.0}) points.emplace_back(std::cos(angle), std::sin(angle), z);
    const int o0 = 0, o1 = 1, a0 = base, a1 = base + 1, b0 = base + 2, b1 = base + 3;
    faces.insert(faces.end(), {{o0, b0, a0}, {o1, a1, b1}, {o0, a0, a1}, {o0, a1, o1},
                               {a0, b0, b1}, {a0, b1, a1}, {b0, o0, o1}, {b0, o1, b1}});
  }
  return appendTriangles(TriangleMesh{Eigen::Matrix3Xd(3, 0), Eigen::Matrix3Xi(3, 0)}, points, faces);
}

TEST(MeshRepair, MeshWithoutDefectsIsLeftBitIdentical) {
  for (const TriangleMesh& original :
       {makeCube(10.0), test::makeIcosphere(20.0, 2), makeCellUnion({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}, 5.0)}) {
    TriangleMesh mesh = original;
    const MeshRepairReport report = repairMesh(mesh);
    expectIdentical(mesh, original);
    EXPECT_FALSE(report.foundDefects());
    EXPECT_EQ(report.describe(), "");
  }
}

TEST(MeshRepair, CollapsedTrianglesAreRemovedAndTheVolumeIsUnchanged) {
  const TriangleMesh cube = makeCube(10.0);
  TriangleMesh mesh = appendTriangles(cube, {}, {{0, 0, 1}, {2, 6, 6}});
  const MeshRepairReport report = repairMesh(mesh);
  EXPECT_EQ(report.collapsed_triangles, 2);
  EXPECT_EQ(report.non_manifold_edges, 0) << "collapsed triangles do not make an edge non-manifold";
  expectIdentical(mesh, cube);
  EXPECT_NEAR(report.volume_after_mm3, report.volume_before_mm3, 1e-9);
}

TEST(MeshRepair, BackToBackPairOnAnEdgeIsRemovedAndTheMeshBecomesManifold) {
  // Two triangles on vertices 0, 1 and a new vertex 8, wound against each other: a flap of no
  // volume on the cube's edge 0–1, what merging coincident vertices makes of a flat pocket.
  const TriangleMesh cube = makeCube(10.0);
  TriangleMesh mesh = appendTriangles(cube, {{5.0, -3.0, 0.0}}, {{0, 1, 8}, {1, 0, 8}});
  ASSERT_EQ(checkMesh(mesh).non_manifold_edges, 1);
  const MeshRepairReport report = repairMesh(mesh);
  EXPECT_EQ(report.non_manifold_edges, 1);
  EXPECT_EQ(report.back_to_back_pairs, 1);
  EXPECT_EQ(report.dropped_vertices, 1);
  expectSolidWithoutPinches(mesh);
  expectIdentical(mesh, cube);
  EXPECT_NEAR(calcVolume(mesh), report.volume_before_mm3, 1e-9);
}

TEST(MeshRepair, ExactDuplicatesOfATriangleAreRemovedDownToOne) {
  const TriangleMesh cube = makeCube(10.0);
  const Eigen::Vector3i t = cube.triangles.col(3);
  TriangleMesh mesh = appendTriangles(cube, {}, {{t[1], t[2], t[0]}, {t[0], t[1], t[2]}});
  ASSERT_EQ(checkMesh(mesh).non_manifold_edges, 3);
  const MeshRepairReport report = repairMesh(mesh);
  EXPECT_EQ(report.duplicate_triangles, 2);
  expectSolidWithoutPinches(mesh);
  EXPECT_NEAR(calcVolume(mesh), 1000.0, 1e-9);
}

TEST(MeshRepair, PinchedEdgeIsSplitAndTheMeshBecomesManifold) {
  // Two 10 mm cubes touching along the edge x = y = 10 mm.
  TriangleMesh mesh = makeCellUnion({{0, 0, 0}, {1, 1, 0}}, 10.0);
  ASSERT_EQ(checkMesh(mesh).non_manifold_edges, 1);
  ASSERT_EQ(mesh.countVertices(), 14);
  const MeshRepairReport report = repairMesh(mesh);
  EXPECT_EQ(report.non_manifold_edges, 1);
  EXPECT_EQ(report.vertex_copies, 2);
  EXPECT_EQ(report.removed_shells, 0) << "both cubes enclose real volume";
  expectSolidWithoutPinches(mesh);
  EXPECT_EQ(mesh.countVertices(), 16);
  EXPECT_EQ(countComponents(mesh), 2);
  EXPECT_NEAR(calcVolume(mesh), 2000.0, 1e-9);
  EXPECT_NEAR(report.volume_after_mm3, report.volume_before_mm3, 1e-9);
  const std::string text = report.describe();
  EXPECT_TRUE(contains(text, "1 non-manifold edge repaired")) << text;
  EXPECT_TRUE(contains(text, "added 2 vertex copies")) << text;
}

TEST(MeshRepair, PinchedEdgeOfOneSurfaceIsSplitAndTheSurfaceStaysOnePiece) {
  // A ring of seven cells whose ends touch along one edge: the surface meets itself there,
  // as the sacrum's does.
  TriangleMesh mesh = makeCellUnion({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 1, 0}, {2, 2, 0}, {1, 2, 0}, {0, 1, 0}}, 10.0);
  ASSERT_EQ(checkMesh(mesh).non_manifold_edges, 1);
  ASSERT_EQ(countComponents(mesh), 1);
  const MeshRepairReport report = repairMesh(mesh);
  EXPECT_EQ(report.vertex_copies, 2);
  expectSolidWithoutPinches(mesh);
  EXPECT_EQ(countComponents(mesh), 1);
  EXPECT_NEAR(calcVolume(mesh), 7000.0, 1e-9);
}

TEST(MeshRepair, ThreeSheetsOnOneEdgeAreAllSeparated) {
  TriangleMesh mesh = makePrismsOnOneEdge(3);
  const double volume = calcVolume(mesh);
  ASSERT_NEAR(volume, 3 * 0.5 * std::sin(M_PI / 3.0), 1e-12);
  const MeshRepairReport report = repairMesh(mesh);
  EXPECT_EQ(report.non_manifold_edges, 1);
  EXPECT_EQ(report.vertex_copies, 4) << "both ends of the edge, two copies each";
  expectSolidWithoutPinches(mesh);
  EXPECT_EQ(countComponents(mesh), 3);
  EXPECT_NEAR(calcVolume(mesh), volume, 1e-12);
}

TEST(MeshRepair, PinchedVertexIsSplitAndEachCubeKeepsItsOwnCorner) {
  // Two cubes touching at the corner (10, 10, 10) mm: every edge is manifold, the vertex is not.
  TriangleMesh mesh = makeCellUnion({{0, 0, 0}, {1, 1, 1}}, 10.0);
  ASSERT_TRUE(checkMesh(mesh).listProblems().empty());
  const MeshRepairReport report = repairMesh(mesh);
  EXPECT_EQ(report.pinched_vertices, 1);
  EXPECT_EQ(report.vertex_copies, 1);
  EXPECT_EQ(mesh.countVertices(), 16);
  EXPECT_EQ(countComponents(mesh), 2);
  expectSolidWithoutPinches(mesh);
  EXPECT_NEAR(calcVolume(mesh), 2000.0, 1e-9);
}

TEST(MeshRepair, ShellHangingAtAPinchIsRemovedWhenItsVolumeIsNegligible) {
  // A 1 µm cube on the corner (10, 10, 10) mm of a 10 mm cube: 1e-9 mm³ against 1000 mm³.
  const TriangleMesh cube = makeCube(10.0);
  const TriangleMesh speck = makeCube(1e-3, 10.0);
  std::vector<Eigen::Vector3d> points;
  for (int v = 1; v < 8; ++v) points.push_back(speck.vertices_mm.col(v));
  std::vector<std::array<int, 3>> faces;
  for (int t = 0; t < 12; ++t) {
    std::array<int, 3> f;
    for (int c = 0; c < 3; ++c) f[std::size_t(c)] = speck.triangles(c, t) == 0 ? 7 : 7 + speck.triangles(c, t);
    faces.push_back(f);
  }
  const TriangleMesh with_speck = appendTriangles(cube, points, faces);
  ASSERT_EQ(with_speck.vertices_mm.col(7), speck.vertices_mm.col(0));

  TriangleMesh mesh = with_speck;
  const MeshRepairReport report = repairMesh(mesh);
  EXPECT_EQ(report.removed_shells, 1);
  EXPECT_EQ(report.removed_shell_triangles, 12);
  EXPECT_NEAR(report.removed_shell_volume_mm3, 1e-9, 1e-15);
  expectIdentical(mesh, cube);
  EXPECT_NEAR(report.volume_after_mm3, report.volume_before_mm3, 1e-6 * 1000.0);

  // With no allowance the speck stays, split off at its own corner.
  TriangleMesh kept = with_speck;
  MeshRepairOptions strict;
  strict.max_detached_shell_volume_fraction = 0.0;
  const MeshRepairReport kept_report = repairMesh(kept, strict);
  EXPECT_EQ(kept_report.removed_shells, 0);
  EXPECT_EQ(countComponents(kept), 2);
  expectSolidWithoutPinches(kept);
}

TEST(MeshRepair, FlatPocketOnAnEdgeIsRemovedAndTheMeshBecomesManifold) {
  // A flat tetrahedron (corners 0, 1 of the cube and two points beside it, all in z = 0)
  // sharing the cube's edge 0–1: a closed shell of no volume, as the segmentation leaves.
  const TriangleMesh cube = makeCube(10.0);
  TriangleMesh mesh = appendTriangles(cube, {{5.0, -2.0, 0.0}, {4.0, -1.0, 0.0}},
                                      {{0, 9, 1}, {0, 1, 8}, {0, 8, 9}, {1, 9, 8}});
  ASSERT_EQ(checkMesh(mesh).non_manifold_edges, 1);
  const MeshRepairReport report = repairMesh(mesh);
  EXPECT_EQ(report.removed_shells, 1);
  EXPECT_EQ(report.removed_shell_triangles, 4);
  expectSolidWithoutPinches(mesh);
  expectIdentical(mesh, cube);
  EXPECT_NEAR(calcVolume(mesh), report.volume_before_mm3, 1e-9);
}

TEST(MeshRepair, FinOnAnEdgeCannotBeSplitAndIsLeftAsItWas) {
  // One loose triangle on the cube's edge 0–1: three triangles on the edge, two boundary edges.
  const TriangleMesh fin = appendTriangles(makeCube(10.0), {{5.0, -3.0, 0.0}}, {{0, 1, 8}});
  TriangleMesh mesh = fin;
  const MeshRepairReport report = repairMesh(mesh);
  expectIdentical(mesh, fin);
  EXPECT_EQ(report.unsplit_edges, 1);
  EXPECT_TRUE(report.leftDefects());
  EXPECT_TRUE(contains(report.describe(), "could not split 1 non-manifold edge")) << report.describe();
}

TEST(MeshRepair, SurfaceOnTopOfItsReverseIsLeftAsItWas) {
  // Every triangle has a back-to-back twin: removing the pairs would leave nothing.
  const TriangleMesh cube = makeCube(10.0);
  TriangleMesh reversed = cube;
  reversed.triangles.row(1).swap(reversed.triangles.row(2));
  std::vector<std::array<int, 3>> faces;
  for (int t = 0; t < 12; ++t) faces.push_back({reversed.triangles(0, t), reversed.triangles(1, t), reversed.triangles(2, t)});
  const TriangleMesh both = appendTriangles(cube, {}, faces);
  TriangleMesh mesh = both;
  const MeshRepairReport report = repairMesh(mesh);
  expectIdentical(mesh, both);
  EXPECT_TRUE(report.cancels_out);
  EXPECT_TRUE(contains(report.describe(), "back-to-back twin")) << report.describe();
}

}  // namespace
}  // namespace rbfmuscle
