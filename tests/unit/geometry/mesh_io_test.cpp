// SPDX-License-Identifier: Apache-2.0
#include "geometry/mesh_io.h"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <limits>
#include <vector>

#include "geometry/mesh_check.h"
#include "geometry/mesh_measures.h"
#include "geometry/ply_reader.h"
#include "support/eigen_compare.h"
#include "unit/geometry/test_meshes.h"

namespace rbfmuscle {
namespace {

using test::makeCube;
using test::makeTempDir;
using test::modelPath;
using test::writeText;

/// Expects `f` to throw MeshError whose message contains every string in `parts`.
template <typename F>
void expectMeshError(F f, std::initializer_list<std::string> parts) {
  try {
    f();
    FAIL() << "expected MeshError";
  } catch (const MeshError& e) {
    const std::string what = e.what();
    for (const auto& part : parts) EXPECT_NE(what.find(part), std::string::npos) << what;
  }
}

TEST(MeshIo, LoadsShippedPlyWithFileCounts) {
  struct Expected {
    const char* file;
    int vertices, triangles;
  };
  for (const Expected& e : {Expected{"shapes/box.ply", 2648, 5292},
                            Expected{"shapes/rod.ply", 5768, 11532},
                            Expected{"shapes/block.ply", 26, 48},
                            Expected{"shapes/tetrahedron.ply", 4, 4},
                            Expected{"hip/meshes/femur_r.ply", 21230, 42456},
                            Expected{"hip/meshes/gluteus_maximus_r.ply", 9878, 19752},
                            Expected{"hip/meshes/iliacus_r.ply", 6931, 13858},
                            Expected{"hip/meshes/pelvis_r_proxy.ply", 845, 1690}}) {
    const TriangleMesh m = loadMesh(modelPath(e.file));
    EXPECT_EQ(m.countVertices(), e.vertices) << e.file;
    EXPECT_EQ(m.countTriangles(), e.triangles) << e.file;
    EXPECT_GE(m.triangles.minCoeff(), 0) << e.file;
    EXPECT_LT(m.triangles.maxCoeff(), m.countVertices()) << e.file;
  }
}

TEST(MeshIo, ParseMeshFromMemoryEqualsReadingTheFile) {
  for (const char* file : {"shapes/block.ply", "shapes/tetrahedron.ply", "hip/meshes/pelvis_r_proxy.ply"}) {
    std::ifstream in(modelPath(file), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const LoadedMesh from_memory = parseMesh(bytes, modelPath(file));
    const LoadedMesh from_file = readMesh(modelPath(file));
    EXPECT_EQ(from_memory.mesh.vertices_mm, from_file.mesh.vertices_mm) << file;
    EXPECT_EQ(from_memory.mesh.triangles, from_file.mesh.triangles) << file;
  }
  expectMeshError([] { parseMesh("solid x\nendsolid x\n", "memory.stl"); }, {"memory.stl", ".ply and .vtp"});
  expectMeshError([] { parseMesh("ply\nformat ascii 1.0\n", "memory.ply"); }, {"memory.ply", "end_header"});
}

// Found by fuzz_ply: a binary PLY whose only triangle has coinciding corners. Repair removes the
// collapsed triangle, so the loader returned a mesh without triangles, which every later step
// assumes it has.
TEST(MeshIo, AMeshWhoseTrianglesAllCollapseIsRefusedNamingTheFile) {
  const std::string path = std::string(RBFMUSCLE_SOURCE_DIR) + "/tests/unit/geometry/data/fuzz/all_triangles_collapse.ply";
  expectMeshError([&] { readMesh(path); },
                  {path, "no triangles once collapsed and duplicate triangles are removed (1 in the file)"});
}

TEST(MeshIo, MeshesWithoutDefectsLoadExactlyAsStoredAndWithoutWarning) {
  for (const char* file : {"shapes/box.ply", "shapes/rod.ply", "shapes/block.ply", "shapes/tetrahedron.ply",
                           "hip/meshes/femur_r.ply", "hip/meshes/gluteus_maximus_r.ply", "hip/meshes/iliacus_r.ply",
                           "hip/meshes/pelvis_r_proxy.ply"}) {
    std::vector<std::string> warnings;
    const TriangleMesh m = loadMesh(modelPath(file), [&](const std::string& w) { warnings.push_back(w); });
    EXPECT_TRUE(warnings.empty()) << file << ": " << warnings.front();
    const detail::PlyContent stored = detail::readPly(modelPath(file));
    ASSERT_EQ(m.countVertices(), int(stored.vertices.size())) << file;
    ASSERT_EQ(m.countTriangles(), int(stored.faces.size())) << file;
    bool same = true;
    for (int v = 0; v < m.countVertices(); ++v)
      for (int k = 0; k < 3; ++k) same = same && m.vertices_mm(k, v) == stored.vertices[std::size_t(v)][std::size_t(k)];
    for (int t = 0; t < m.countTriangles(); ++t)
      for (int c = 0; c < 3; ++c) same = same && m.triangles(c, t) == stored.faces[std::size_t(t)][std::size_t(c)];
    EXPECT_TRUE(same) << file << " differs from the file's own vertices and faces";
  }
}

TEST(MeshIo, SubjectPelvisAndPsoasLoadRepairedWithAWarningNamingFileAndCounts) {
  struct Expected {
    const char* file;
    double volume_ml;  // the data's README, rounded to 0.1 ml
    std::vector<std::string> counts;
  };
  for (const Expected& e :
       {Expected{"hip/meshes/pelvis_iliac_r.ply", 346.5, {"2 unused vertices dropped", "1 non-manifold edge repaired"}},
        Expected{"hip/meshes/pelvis_sacrum.ply", 245.7, {"11 unused vertices dropped", "2 non-manifold edges repaired"}},
        Expected{"hip/meshes/pelvis_iliac_l.ply", 364.0, {"1 unused vertex dropped"}},
        Expected{"hip/meshes/psoas_major_r.ply", 103.5,
                 {"25 unused vertices dropped", "3 non-manifold edges and 1 pinched vertex repaired"}}}) {
    const std::string path = modelPath(e.file);
    std::vector<std::string> warnings;
    const TriangleMesh m = loadMesh(path, [&](const std::string& w) { warnings.push_back(w); });
    ASSERT_EQ(warnings.size(), 1u) << e.file;
    EXPECT_EQ(warnings[0].rfind(path + ": ", 0), 0u) << warnings[0];
    for (const std::string& part : e.counts) EXPECT_NE(warnings[0].find(part), std::string::npos) << warnings[0];
    const MeshReport report = checkMesh(m);
    EXPECT_TRUE(report.listProblems().empty()) << e.file << ": " << report.describe();
    EXPECT_EQ(report.components, 1) << e.file;
    EXPECT_NO_THROW(validateMesh(m, e.file));
    EXPECT_NEAR(calcVolume(m) / 1000.0, e.volume_ml, 0.05) << e.file;

    const LoadedMesh loaded = readMesh(path);
    EXPECT_NEAR(loaded.repair.volume_after_mm3, loaded.repair.volume_before_mm3, 1e-6 * loaded.repair.volume_before_mm3)
        << e.file;
    EXPECT_FALSE(loaded.repair.leftDefects()) << e.file;
  }
}

TEST(MeshIo, FlatPocketAsSegmentedIsRemovedWhenLoaded) {
  // As in the subject's meshes: on the cube's edge 0–1 a flat pocket of four triangles whose
  // third corners, 8 and 9, are two vertices at one position. Merging them leaves two
  // collapsed triangles and a back-to-back pair, which go.
  const TriangleMesh cube = makeCube(10.0);
  TriangleMesh pocket = cube;
  pocket.vertices_mm.conservativeResize(3, 10);
  pocket.vertices_mm.col(8) = pocket.vertices_mm.col(9) = Eigen::Vector3d(5.0, -0.1, 0.0);
  pocket.triangles.conservativeResize(3, 16);
  pocket.triangles.rightCols(4) << 0, 1, 1, 9,  //
      8, 9, 8, 8,                                //
      1, 0, 9, 0;
  const auto dir = makeTempDir("pocket");
  const std::string path = (dir / "pocket.ply").string();
  writePly(path, pocket);
  ASSERT_EQ(checkMesh(pocket).non_manifold_edges, 1);

  std::vector<std::string> warnings;
  const TriangleMesh m = loadMesh(path, [&](const std::string& w) { warnings.push_back(w); });
  ASSERT_EQ(warnings.size(), 1u);
  for (const std::string& part : {path + ": ", std::string("1 non-manifold edge repaired"),
                                 std::string("2 collapsed triangles"), std::string("1 back-to-back triangle pair")})
    EXPECT_NE(warnings[0].find(part), std::string::npos) << warnings[0];
  EXPECT_EQ(m.triangles, cube.triangles);
  EXPECT_TRUE(test::isApprox(m.vertices_mm, cube.vertices_mm, 0, 0));
}

TEST(MeshIo, BoxHasFileBounds) {
  // models/shapes/box.ply spans x, z ∈ [−50, 50] mm and y ∈ [10, 90] mm.
  const Eigen::AlignedBox3d box = loadMesh(modelPath("shapes/box.ply")).calcBoundingBox();
  EXPECT_TRUE(test::isApprox(box.min(), Eigen::Vector3d(-50, 10, -50), 0, 1e-9));
  EXPECT_TRUE(test::isApprox(box.max(), Eigen::Vector3d(50, 90, 50), 0, 1e-9));
}

TEST(MeshIo, AsciiStlIsWeldedIntoIndexedCube) {
  const TriangleMesh cube = makeCube(10.0);
  std::string stl = "solid cube\n";
  for (int t = 0; t < cube.countTriangles(); ++t) {
    stl += " facet normal 0 0 0\n  outer loop\n";
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3d p = cube.getCorner(t, c);
      stl += "   vertex " + std::to_string(p.x()) + " " + std::to_string(p.y()) + " " +
             std::to_string(p.z()) + "\n";
    }
    stl += "  endloop\n endfacet\n";
  }
  stl += "endsolid cube\n";
  const auto dir = makeTempDir("stl");
  const TriangleMesh m = loadMesh(writeText(dir / "cube.stl", stl));
  EXPECT_EQ(m.countVertices(), 8);
  EXPECT_EQ(m.countTriangles(), 12);
  for (int t = 0; t < 12; ++t)
    for (int c = 0; c < 3; ++c)
      EXPECT_TRUE(test::isApprox(m.getCorner(t, c), cube.getCorner(t, c), 0, 1e-9));
}

TEST(MeshIo, ObjQuadsAreTriangulated) {
  const auto dir = makeTempDir("obj");
  const std::string path = writeText(dir / "square.obj",
                                     "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
  const TriangleMesh m = loadMesh(path);
  EXPECT_EQ(m.countVertices(), 4);
  EXPECT_EQ(m.countTriangles(), 2);
}

TEST(MeshIo, WritePlyRoundTripIsExact) {
  TriangleMesh m = loadMesh(modelPath("hip/meshes/gluteus_maximus_r.ply"));
  m.vertices_mm.array() += 0.123456789;  // shifted, so the file is not a byte copy
  const auto dir = makeTempDir("roundtrip");
  const std::string path = (dir / "out.ply").string();
  writePly(path, m);
  const TriangleMesh back = loadMesh(path);
  EXPECT_EQ(back.triangles, m.triangles);
  EXPECT_TRUE(test::isApprox(back.vertices_mm, m.vertices_mm, 0, 0));
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1u) << "temporary file left beside the target";
}

TEST(MeshIo, HashIsFnv1a64OfBytes) {
  const auto dir = makeTempDir("hash");
  // Published FNV-1a 64 test vectors: "" and "a".
  EXPECT_EQ(hashFile(writeText(dir / "empty", "")), "cbf29ce484222325");
  EXPECT_EQ(hashFile(writeText(dir / "a", "a")), "af63dc4c8601ec8c");
  EXPECT_EQ(hashFile(modelPath("shapes/box.ply")).size(), 16u);
  EXPECT_NE(hashFile(modelPath("shapes/box.ply")), hashFile(modelPath("shapes/rod.ply")));
  expectMeshError([&] { hashFile((dir / "nothing").string()); }, {"nothing"});
}

TEST(MeshIo, MissingFileNamesFile) {
  expectMeshError([] { loadMesh("/nonexistent/dir/iliacus.ply"); },
                  {"/nonexistent/dir/iliacus.ply", "cannot open"});
}

TEST(MeshIo, GarbageFilesNameFileAndFault) {
  const auto dir = makeTempDir("garbage");
  const std::string ply = writeText(dir / "garbage.ply", "ply\nthis is not a mesh\n\x01\x02");
  expectMeshError([&] { loadMesh(ply); }, {ply, "line 2", "unknown keyword"});
  const std::string stl = writeText(dir / "garbage.stl", "\x01\x02 not an stl file");
  expectMeshError([&] { loadMesh(stl); }, {stl, "assimp"});
}

TEST(MeshIo, TruncatedBinaryPlyNamesFile) {
  const auto dir = makeTempDir("truncated");
  const std::string full = (dir / "full.ply").string();
  writePly(full, makeCube(1.0));
  std::ifstream in(full, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string cut = writeText(dir / "cut.ply", bytes.substr(0, bytes.size() - 7));
  expectMeshError([&] { loadMesh(cut); }, {cut, "truncated"});
}

TEST(MeshIo, AsciiPlyWithQuadsAndExtraProperties) {
  const auto dir = makeTempDir("asciiply");
  const std::string path = writeText(
      dir / "square.ply",
      "ply\r\nformat ascii 1.0\r\ncomment x\r\nelement vertex 4\r\nproperty double x\r\n"
      "property double y\r\nproperty double z\r\nproperty uchar red\r\nelement face 1\r\n"
      "property list uchar int vertex_index\r\nend_header\r\n"
      "0 0 0 1\r\n2 0 0 1\r\n2 3 0 1\r\n0 3 0.5 1\r\n4 0 1 2 3\r\n");
  const TriangleMesh m = loadMesh(path);
  EXPECT_EQ(m.countVertices(), 4);
  EXPECT_EQ(m.countTriangles(), 2);
  EXPECT_TRUE(test::isApprox(m.vertices_mm.col(3), Eigen::Vector3d(0, 3, 0.5), 0, 0));
}

TEST(MeshIo, MeshWithoutTrianglesNamesFile) {
  const auto dir = makeTempDir("notriangles");
  const std::string path = writeText(dir / "points.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\n");
  expectMeshError([&] { loadMesh(path); }, {path});
  try {
    loadMesh(path);
  } catch (const MeshError& e) {
    const std::string what = e.what();
    EXPECT_TRUE(what.find("no triangles") != std::string::npos ||
                what.find("assimp") != std::string::npos)
        << what;
  }
}

TEST(MeshIo, NanVertexNamesFileAndVertex) {
  TriangleMesh m = makeCube(10.0);
  m.vertices_mm(1, 5) = std::numeric_limits<double>::quiet_NaN();
  const auto dir = makeTempDir("nan");
  const std::string path = (dir / "nan.ply").string();
  writePly(path, m);
  expectMeshError([&] { loadMesh(path); }, {path, "non-finite", "vertex 5"});
}

TEST(MeshIo, WriteToMissingDirectoryNamesFile) {
  expectMeshError([] { writePly("/nonexistent/dir/out.ply", makeCube(1.0)); },
                  {"/nonexistent/dir/out.ply"});
}

/// An ASCII PLY tetrahedron with its corners scaled by `scale`.
std::string tetrahedronPly(double scale) {
  std::ostringstream text;
  text.precision(17);
  text << "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
          "element face 4\nproperty list uchar int vertex_indices\nend_header\n";
  const double corners[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (const auto& c : corners) text << c[0] * scale << ' ' << c[1] * scale << ' ' << c[2] * scale << '\n';
  text << "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  return text.str();
}

TEST(MeshIo, MeshPathThatIsADeviceIsRefusedWithoutReading) {
  // Reading /dev/zero never ends: the loaders refuse anything but a regular file up front.
  expectMeshError([] { loadMesh("/dev/zero"); }, {"/dev/zero", "is a character device, not a regular file"});
  expectMeshError([] { detail::readPly("/dev/urandom"); }, {"/dev/urandom", "character device"});
  expectMeshError([] { hashFile("/dev/zero"); }, {"/dev/zero", "character device"});
  const auto dir = makeTempDir("mesh_io_device");
  const std::string link = (dir / "zero.ply").string();
  std::filesystem::remove(link);
  std::filesystem::create_symlink("/dev/zero", link);
  expectMeshError([&] { loadMesh(link); }, {link, "character device"});
}

TEST(MeshIo, MeshPathThatIsAFifoOrDirectoryIsRefused) {
  const auto dir = makeTempDir("mesh_io_fifo");
  const std::string fifo = (dir / "pipe.ply").string();
  std::filesystem::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  expectMeshError([&] { loadMesh(fifo); }, {fifo, "is a FIFO (named pipe), not a regular file"});
  expectMeshError([&] { loadMesh(dir.string()); }, {dir.string(), "is a directory, not a regular file"});
}

TEST(MeshIo, PlyCountBeyondTheFileSizeIsRefusedBeforeAllocation) {
  // A huge count used to end in a bare std::bad_alloc.
  const auto dir = makeTempDir("mesh_io_counts");
  const std::string huge = writeText(dir / "huge.ply",
                                     "ply\nformat binary_little_endian 1.0\nelement vertex 2000000000\n"
                                     "property double x\nproperty double y\nproperty double z\nelement face 0\n"
                                     "property list uchar int vertex_indices\nend_header\n");
  expectMeshError([&] { loadMesh(huge); },
                  {huge, "declares 2000000000 'vertex' records of at least 24 bytes each, but only 0 bytes"});
  const std::string too_many = writeText(dir / "too_many.ply",
                                         "ply\nformat ascii 1.0\nelement vertex 99999999999\nproperty float x\n"
                                         "property float y\nproperty float z\nend_header\n");
  expectMeshError([&] { loadMesh(too_many); }, {too_many, "expected a whole number of records from 0 to 2147483647"});
  const std::string faces = writeText(dir / "faces.ply", tetrahedronPly(1.0).replace(
                                                             tetrahedronPly(1.0).find("face 4"), 6, "face 400"));
  expectMeshError([&] { loadMesh(faces); }, {faces, "400 'face' records"});
}

TEST(MeshIo, MeshAtScale1e30IsRefusedAsImplausible) {
  const auto dir = makeTempDir("mesh_io_scale_big");
  const std::string big = writeText(dir / "big.ply", tetrahedronPly(1e30));
  expectMeshError([&] { loadMesh(big); }, {big, "has a coordinate of magnitude above 1e+06"});
}

TEST(MeshIo, MeshAtScale1eMinus30IsRefusedAsCollapsed) {
  const auto dir = makeTempDir("mesh_io_scale_tiny");
  const std::string tiny = writeText(dir / "tiny.ply", tetrahedronPly(1e-30));
  expectMeshError([&] { loadMesh(tiny); }, {tiny, "the mesh spans only 1e-30", "less than 1e-06"});
  // Within the bounds it loads.
  EXPECT_EQ(loadMesh(writeText(dir / "small.ply", tetrahedronPly(1e-5))).countTriangles(), 4);
  EXPECT_EQ(loadMesh(writeText(dir / "large.ply", tetrahedronPly(1e5))).countTriangles(), 4);
}

}  // namespace
}  // namespace rbfmuscle
