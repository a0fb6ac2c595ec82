// SPDX-License-Identifier: Apache-2.0
#include "geometry/solid_mesh.h"

#include <gtest/gtest.h>

#include <vector>

#include "geometry/mesh_check.h"
#include "geometry/mesh_error.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_measures.h"
#include "unit/geometry/test_meshes.h"

namespace rbfmuscle {
namespace {

using test::appendTriangles;
using test::makeCube;
using test::makeTempDir;
using test::modelPath;

/// The message of the MeshError that loading `path` as a solid throws; fails when none is thrown.
std::string loadError(const std::string& path) {
  try {
    loadSolidMesh(path, SolidMeshOptions{false, nullptr});
  } catch (const MeshError& e) {
    return e.what();
  }
  ADD_FAILURE() << path << ": expected MeshError";
  return "";
}

/// Writes `mesh` to a fresh directory `name` as `<name>.ply` and returns the path.
std::string writeMesh(const std::string& name, const TriangleMesh& mesh) {
  const std::string path = (makeTempDir("solid_" + name) / (name + ".ply")).string();
  writePly(path, mesh);
  return path;
}

void expectContainsAll(const std::string& text, std::initializer_list<std::string> parts) {
  for (const std::string& part : parts) EXPECT_NE(text.find(part), std::string::npos) << "'" << part << "' in: " << text;
}

TEST(SolidMesh, SubjectPelvisAndPsoasLoadAsClosedOutwardSolids) {
  for (const char* file : {"hip/meshes/pelvis_iliac_r.ply", "hip/meshes/pelvis_sacrum.ply",
                           "hip/meshes/pelvis_iliac_l.ply", "hip/meshes/psoas_major_r.ply"}) {
    std::vector<std::string> warnings;
    const TriangleMesh m =
        loadSolidMesh(modelPath(file), SolidMeshOptions{false, [&](const std::string& w) { warnings.push_back(w); }});
    EXPECT_EQ(warnings.size(), 1u) << file;
    const MeshReport report = checkMesh(m);
    EXPECT_TRUE(report.isWatertight()) << file << ": " << report.describe();
    EXPECT_TRUE(report.listProblems().empty()) << file << ": " << report.describe();
    EXPECT_GT(report.signed_volume_mm3, 0.0) << file;
  }
}

TEST(SolidMesh, OpenMeshIsRejectedNamingFileAndBoundaryEdges) {
  // One triangle of the box removed: its three edges are open.
  const std::string path = writeMesh("open", test::removeTriangle(loadMesh(modelPath("shapes/box.ply")), 17));
  expectContainsAll(loadError(path), {path + ": ", "3 boundary edges", "not watertight"});
}

TEST(SolidMesh, OpenHalfSphereIsRejectedNamingItsManyBoundaryEdges) {
  TriangleMesh sphere = test::makeIcosphere(10.0, 2);
  std::vector<std::array<int, 3>> upper;
  for (int t = 0; t < sphere.countTriangles(); ++t)
    if (sphere.getCorner(t, 0).z() + sphere.getCorner(t, 1).z() + sphere.getCorner(t, 2).z() > 0.0)
      upper.push_back({sphere.triangles(0, t), sphere.triangles(1, t), sphere.triangles(2, t)});
  TriangleMesh half{sphere.vertices_mm, Eigen::Matrix3Xi(3, 0)};
  half = appendTriangles(half, {}, upper);
  const int boundary = checkMesh(half).boundary_edges;
  ASSERT_GT(boundary, 10);
  const std::string path = writeMesh("half_sphere", half);
  expectContainsAll(loadError(path), {path + ": ", std::to_string(boundary) + " boundary edges", "not watertight"});
}

TEST(SolidMesh, FinOnAnEdgeIsRejectedNamingFileDefectsAndWhatCouldNotBeRepaired) {
  const std::string path = writeMesh("fin", appendTriangles(makeCube(10.0), {{5.0, -3.0, 0.0}}, {{0, 1, 8}}));
  std::vector<std::string> warnings;
  EXPECT_THROW(loadSolidMesh(path, SolidMeshOptions{false, [&](const std::string& w) { warnings.push_back(w); }}),
               MeshError);
  ASSERT_EQ(warnings.size(), 1u);
  expectContainsAll(warnings[0], {path + ": ", "could not split 1 non-manifold edge"});
  expectContainsAll(loadError(path), {path + ": ", "1 non-manifold edges", "2 boundary edges",
                                      "the loader could not repair it", "could not split 1 non-manifold edge"});
}

TEST(SolidMesh, SurfaceOverItsReverseIsRejectedAsEnclosingNothing) {
  // The cube and the same cube wound inward: every triangle doubled back-to-back.
  const TriangleMesh cube = makeCube(10.0);
  std::vector<std::array<int, 3>> reversed;
  for (int t = 0; t < 12; ++t) reversed.push_back({cube.triangles(0, t), cube.triangles(2, t), cube.triangles(1, t)});
  const std::string path = writeMesh("doubled", appendTriangles(cube, {}, reversed));
  expectContainsAll(loadError(path), {path + ": ", "non-manifold edges", "back-to-back twin"});
}

TEST(SolidMesh, PinchedEdgeOnAnInconsistentlyWoundMeshIsRejectedNamingBoth) {
  // Two cubes on one edge, one triangle of the first flipped: the split is not attempted on a
  // mesh that is not consistently wound, and both defects are named.
  TriangleMesh mesh = test::makeCellUnion({{0, 0, 0}, {1, 1, 0}}, 10.0);
  std::swap(mesh.triangles(1, 0), mesh.triangles(2, 0));
  const std::string path = writeMesh("pinch_flipped", mesh);
  expectContainsAll(loadError(path),
                    {path + ": ", "1 non-manifold edges", "inconsistently wound edges", "could not split"});
}

TEST(SolidMesh, PinchedEdgeOnAnInconsistentlyWoundMeshIsRepairedWhenTheWindingMayBeFixed) {
  TriangleMesh mesh = test::makeCellUnion({{0, 0, 0}, {1, 1, 0}}, 10.0);
  std::swap(mesh.triangles(1, 0), mesh.triangles(2, 0));
  const std::string path = writeMesh("pinch_flipped_fixed", mesh);
  std::vector<std::string> warnings;
  const TriangleMesh m =
      loadSolidMesh(path, SolidMeshOptions{true, [&](const std::string& w) { warnings.push_back(w); }});
  ASSERT_EQ(warnings.size(), 1u);
  expectContainsAll(warnings[0], {path + ": ", "after rewinding: 1 non-manifold edge repaired"});
  EXPECT_TRUE(checkMesh(m).listProblems().empty()) << checkMesh(m).describe();
  EXPECT_NEAR(calcVolume(m), 2000.0, 1e-9);
}

TEST(SolidMesh, InwardWoundMeshIsRejectedUnlessTheWindingMayBeFixed) {
  TriangleMesh inward = makeCube(10.0);
  inward.triangles.row(1).swap(inward.triangles.row(2));
  const std::string path = writeMesh("inward", inward);
  expectContainsAll(loadError(path), {path + ": ", "is not positive"});
  const TriangleMesh fixed = loadSolidMesh(path, SolidMeshOptions{true, nullptr});
  EXPECT_NEAR(calcVolume(fixed), 1000.0, 1e-9);
}

TEST(SolidMesh, PinchedEdgeIsRepairedWithAWarningNamingTheFile) {
  const std::string path = writeMesh("pinched", test::makeCellUnion({{0, 0, 0}, {1, 1, 0}}, 10.0));
  std::vector<std::string> warnings;
  const TriangleMesh m =
      loadSolidMesh(path, SolidMeshOptions{false, [&](const std::string& w) { warnings.push_back(w); }});
  ASSERT_EQ(warnings.size(), 1u);
  expectContainsAll(warnings[0], {path + ": ", "1 non-manifold edge repaired", "added 2 vertex copies"});
  EXPECT_NEAR(calcVolume(m), 2000.0, 1e-9);
}

}  // namespace
}  // namespace rbfmuscle
