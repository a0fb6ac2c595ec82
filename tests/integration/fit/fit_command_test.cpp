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
                                  std::string("--centres 5") + out, kShapes + "box.ply --gamma 2" + out}) {
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

}  // namespace
}  // namespace rbfmuscle
