// SPDX-License-Identifier: Apache-2.0
/// `rbfmuscle fit` end to end: the last stdout line is the JSON figures, the
/// .rbf reads back, the PLY is closed; bad input fails with a clear message
/// and leaves no output file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>

#include "fit/rbf_file.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_io.h"
#include "support/run_host.h"
#include "unit/geometry/test_meshes.h"

namespace rbfmuscle {
namespace {

namespace fs = std::filesystem;
using test::HostResult;

const std::string kShapes = std::string(RBFMUSCLE_SOURCE_DIR) + "/models/shapes/";
const std::string kSmall = " --halton 4000 --metric-points 100000 --cell-mm 1.5 --quiet";

fs::path outDir(const std::string& name) {
  const fs::path dir = fs::path(RBFMUSCLE_BINARY_DIR) / "test_out/fit" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

HostResult runFit(const std::string& args, const std::string& name) {
  return test::runHost("fit " + args, "fit", name);
}

std::string lastLine(const std::string& text) {
  std::string trimmed = text;
  while (!trimmed.empty() && trimmed.back() == '\n') trimmed.pop_back();
  return trimmed.substr(trimmed.find_last_of('\n') + 1);
}

double jsonNumber(const std::string& json, const std::string& key) {
  std::smatch match;
  const std::regex pattern("\"" + key + "\": ([-0-9.eE+]+)");
  if (!std::regex_search(json, match, pattern)) return std::nan("");
  return std::stod(match[1]);
}

TEST(FitCommand, WritesSurfaceMeshAndFigures) {
  const fs::path dir = outDir("box");
  const HostResult r = runFit(kShapes + "box.ply --centres 80 -o " + (dir / "box.rbf").string() +
                                  " --surface " + (dir / "box_surface.ply").string() + kSmall,
                              "box");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string json = lastLine(r.out);
  ASSERT_EQ(json.front(), '{') << json;
  for (const char* key : {"jaccard", "mean_distance_mm", "p95_distance_mm", "max_distance_mm",
                          "volume_ratio", "centres", "seconds"})
    EXPECT_TRUE(std::isfinite(jsonNumber(json, key))) << key << " in " << json;
  EXPECT_EQ(jsonNumber(json, "centres"), 80);
  EXPECT_GT(jsonNumber(json, "jaccard"), 0.9);

  const RbfSurface surface = readRbfFile((dir / "box.rbf").string());
  EXPECT_EQ(surface.field.getNumCentres(), 80);
  EXPECT_EQ(surface.source_mesh, "box.ply");
  EXPECT_EQ(surface.source_hash, hashFile(kShapes + "box.ply"));
  const TriangleMesh mesh = loadMesh((dir / "box_surface.ply").string());
  const MeshReport report = checkMesh(mesh);
  EXPECT_TRUE(report.isWatertight()) << report.describe();
  EXPECT_EQ(report.components, 1);
  // The PLY is in the source frame: box.ply spans y ∈ [10, 90] mm.
  EXPECT_NEAR(mesh.calcBoundingBox().center().y(), 50.0, 2.0);
}

TEST(FitCommand, OutOfMovesTheMeshOutOfTheSolidsBeforeTheFit) {
  // A solid over the box's top 4 mm (box.ply spans y ∈ [10, 90] mm, x and z ∈ [−50, 50] mm).
  const fs::path dir = outDir("out_of");
  TriangleMesh lid = test::makeCube(200.0);
  lid.vertices_mm.colwise() += Eigen::Vector3d(-100.0, 86.0, -100.0);
  writePly((dir / "lid.ply").string(), lid);
  const HostResult r = runFit(kShapes + "box.ply --centres 80 -o " + (dir / "box.rbf").string() + " --out-of " +
                                  (dir / "lid.ply").string() + kSmall,
                              "out_of");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("box.ply: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("mm inside the solids it must not enter (the deepest 4 mm, in " + (dir / "lid.ply").string()),
            std::string::npos)
      << r.err;
  // The fit's target is the moved box, its top 0.3 mm below the lid's face: 100 × 75.7 × 100 mm.
  EXPECT_NEAR(jsonNumber(lastLine(r.out), "mesh_volume_mm3"), 100.0 * (86.0 - 0.3 - 10.0) * 100.0, 1.0) << r.out;
  // The cache still names the mesh file.
  EXPECT_EQ(readRbfFile((dir / "box.rbf").string()).source_hash, hashFile(kShapes + "box.ply"));
}

TEST(FitCommand, OutOfAMissingSolidFailsNamingItWithoutOutput) {
  const fs::path dir = outDir("out_of_missing");
  const HostResult r = runFit(kShapes + "box.ply --centres 10 -o " + (dir / "x.rbf").string() + " --out-of " +
                                  kShapes + "no_such_solid.ply",
                              "out_of_missing");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("no_such_solid.ply"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "x.rbf"));
}

TEST(FitCommand, MissingMeshFailsWithoutOutput) {
  const fs::path dir = outDir("missing");
  const HostResult r = runFit(kShapes + "nothing.ply --centres 10 -o " + (dir / "x.rbf").string(), "missing");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("nothing.ply"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "x.rbf"));
  EXPECT_FALSE(fs::exists(dir / "x.rbf.partial"));
}

TEST(FitCommand, OpenMeshIsRefusedAsNotWatertight) {
  const fs::path dir = outDir("open");
  // Drop the last triangle of the block: an open boundary.
  TriangleMesh open = loadMesh(kShapes + "block.ply");
  open.triangles.conservativeResize(3, open.triangles.cols() - 1);
  writePly((dir / "open_block.ply").string(), open);
  const HostResult r = runFit((dir / "open_block.ply").string() + " --centres 10 -o " + (dir / "x.rbf").string(), "open");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("open_block.ply"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("watertight"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "x.rbf"));
}

TEST(FitCommand, BadCommandLinesExitWithUsage) {
  const fs::path dir = outDir("usage");
  const std::string out = " -o " + (dir / "x.rbf").string();
  for (const std::string& args : {kShapes + "box.ply --centres ten" + out, kShapes + "box.ply --centres 0" + out,
                                  kShapes + "box.ply --bogus" + out, kShapes + "box.ply --centres 5",
                                  std::string("--centres 5") + out, kShapes + "box.ply --gamma 2" + out,
                                  kShapes + "box.ply --crumb-margin-mm -1" + out,
                                  kShapes + "box.ply --check-slope 1.5" + out,
                                  kShapes + "box.ply --centres 5 --centres 6" + out,
                                  kShapes + "box.ply --centres 5 --output y.rbf" + out,
                                  kShapes + "box.ply --global-search 0.01,0.1,1e300" + out,
                                  kShapes + "box.ply --global-search 0.01,0.1,2.5" + out}) {
    const HostResult r = runFit(args, "usage");
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find("rbfmuscle: error: fit:"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(fs::exists(dir / "x.rbf"));
}

TEST(FitCommand, UnwritableOutputFailsBeforeFitting) {
  const HostResult r = runFit(kShapes + "box.ply --centres 10 -o /nonexistent_dir/x.rbf", "unwritable");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("/nonexistent_dir/x.rbf: cannot write"), std::string::npos) << r.err;
}

/// Options that suit the 1 mm tetrahedron (as scripts/fit_table.sh fits it).
const std::string kTetrahedronOptions =
    " --centres 30 --clamp-mm 0.1 --normal-offset-mm 0.02 --cell-mm 0.02 --shapes 5,10,20,50,100,200,500,1000"
    " --halton 4000 --metric-points 100000 --quiet";

/// The tetrahedron of models/shapes (1 mm) written `copies` times, copy k shifted by k·shift_mm in x.
TriangleMesh tetrahedra(int copies, double shift_mm) {
  const TriangleMesh one = loadMesh(kShapes + "tetrahedron.ply");
  TriangleMesh all;
  all.vertices_mm.resize(3, one.countVertices() * copies);
  all.triangles.resize(3, one.countTriangles() * copies);
  for (int k = 0; k < copies; ++k) {
    all.vertices_mm.middleCols(k * one.countVertices(), one.countVertices()) =
        one.vertices_mm.colwise() + Eigen::Vector3d(k * shift_mm, 0, 0);
    all.triangles.middleCols(k * one.countTriangles(), one.countTriangles()) =
        one.triangles.array() + k * one.countVertices();
  }
  return all;
}

std::string fileBytes(const fs::path& path) { return test::readText(path); }

TEST(FitCommand, OutputThatIsTheInputMeshIsRefusedAndTheMeshKept) {
  // `fit MESH -o MESH` used to overwrite the mesh with the .rbf and exit 0.
  const fs::path dir = outDir("output_is_input");
  const fs::path mesh = dir / "tet.ply";
  fs::copy_file(kShapes + "tetrahedron.ply", mesh);
  const std::string before = fileBytes(mesh);
  HostResult r = runFit(mesh.string() + " -o " + mesh.string() + kTetrahedronOptions, "output_is_input");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("rbfmuscle: error: fit: -o " + mesh.string() + " is the input mesh " + mesh.string() +
                       "; refusing to overwrite it"),
            std::string::npos)
      << r.err;
  // The same file under another name: a hard link and a path with '..' in it.
  fs::create_hard_link(mesh, dir / "link.ply");
  r = runFit(mesh.string() + " -o " + (dir / "link.ply").string() + kTetrahedronOptions, "output_is_input_link");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("is the input mesh"), std::string::npos) << r.err;
  r = runFit(mesh.string() + " -o x.rbf --surface " + (dir / ".." / dir.filename() / "tet.ply").string() +
                 kTetrahedronOptions,
             "output_is_input_surface");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("fit: --surface"), std::string::npos) << r.err;
  EXPECT_EQ(fileBytes(mesh), before);
  EXPECT_EQ(fileBytes(dir / "link.ply"), before);
}

TEST(FitCommand, SurfaceAndOutputTheSameFileAreRefused) {
  // `-o X.rbf --surface X.rbf` used to leave a PLY where the .rbf should be.
  const fs::path dir = outDir("surface_is_output");
  const std::string out = (dir / "x.rbf").string();
  const HostResult r = runFit(kShapes + "tetrahedron.ply -o " + out + " --surface " + out + kTetrahedronOptions,
                              "surface_is_output");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("fit: --surface " + out + " and -o " + out + " are the same file"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST(FitCommand, OutputThatIsADeviceIsNotReplaced) {
  const HostResult r = runFit(kShapes + "tetrahedron.ply -o /dev/null" + kTetrahedronOptions, "output_device");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("/dev/null: output exists and is a character device; refusing to replace it"),
            std::string::npos)
      << r.err;
}

TEST(FitCommand, MeshThatIsADeviceIsRefusedWithoutReading) {
  // A mesh path naming a device (here through a .ply link to /dev/zero) used to hang.
  const fs::path dir = outDir("device");
  fs::create_symlink("/dev/zero", dir / "zero.ply");
  const HostResult r = runFit((dir / "zero.ply").string() + " -o " + (dir / "x.rbf").string() + kTetrahedronOptions,
                              "device");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("zero.ply: is a character device, not a regular file (expected a mesh file)"), std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir / "x.rbf"));
}

TEST(FitCommand, MeshAtScale1e30IsRefusedInsteadOfAnEmptyFit) {
  // It used to report success with Jaccard 0, volume 0 and an empty surface.
  const fs::path dir = outDir("scale_1e30");
  TriangleMesh big = loadMesh(kShapes + "tetrahedron.ply");
  big.vertices_mm *= 1e30;
  writePly((dir / "big.ply").string(), big);
  const HostResult r = runFit((dir / "big.ply").string() + " -o " + (dir / "x.rbf").string() + kSmall, "scale_1e30");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("big.ply: vertex 0 (9.42809e+29, 0, -3.33333e+29)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("has a coordinate of magnitude above 1e+06"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "x.rbf"));
}

TEST(FitCommand, MeshTooSmallForTheOptionsIsRefusedInsteadOfAnEmptyFit) {
  // The 1 mm tetrahedron with the default 1 mm cell: nothing could be measured.
  const fs::path dir = outDir("too_small");
  const HostResult r =
      runFit(kShapes + "tetrahedron.ply --centres 10 -o " + (dir / "x.rbf").string() + " --quiet", "too_small");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("tetrahedron.ply: the mesh spans 1.63299 mm, less than 4 cells of the extracted surface (cell 1 mm)"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir / "x.rbf"));
}

TEST(FitCommand, MeshOfTwoSeparatePiecesFitsWithAWarning) {
  const fs::path dir = outDir("two_pieces");
  writePly((dir / "two.ply").string(), tetrahedra(2, 2.0));
  const HostResult r = runFit((dir / "two.ply").string() + " -o " + (dir / "x.rbf").string() + kTetrahedronOptions,
                              "two_pieces");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("rbfmuscle: warning: " + (dir / "two.ply").string() + ": the mesh has 2 separate pieces"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("crosses itself"), std::string::npos) << r.err;
}

TEST(FitCommand, SelfIntersectingMeshFitsWithAWarning) {
  const fs::path dir = outDir("crossing");
  writePly((dir / "crossing.ply").string(), tetrahedra(2, 0.3));
  const HostResult r = runFit(
      (dir / "crossing.ply").string() + " -o " + (dir / "x.rbf").string() + kTetrahedronOptions, "crossing");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("rbfmuscle: warning: " + (dir / "crossing.ply").string() + ": the mesh crosses itself: "),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("pairs of triangles intersect (e.g. triangles "), std::string::npos) << r.err;
}

TEST(FitCommand, MeshWithoutSuchDefectsFitsWithoutAWarningAboutTheMesh) {
  const fs::path dir = outDir("clean");
  const HostResult r = runFit(kShapes + "tetrahedron.ply -o " + (dir / "x.rbf").string() + kTetrahedronOptions, "clean");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  // The mesh is one closed piece that does not cross itself (a warning about the fitted
  // surface, which a 1 mm tetrahedron's sharp edges can split, is another matter).
  EXPECT_EQ(r.err.find("separate pieces"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("crosses itself"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace rbfmuscle
