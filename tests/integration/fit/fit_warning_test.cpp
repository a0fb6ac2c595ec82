// SPDX-License-Identifier: Apache-2.0
/// `rbfmuscle fit` does not report a surface in pieces as a plain success: it warns on
/// stderr, naming the mesh and the figures, and still writes the outputs.
#include <gtest/gtest.h>

#include <filesystem>

#include "support/run_host.h"

namespace rbfmuscle {
namespace {

namespace fs = std::filesystem;

const std::string kShapes = std::string(RBFMUSCLE_SOURCE_DIR) + "/models/shapes/";
const std::string kSmall = " --halton 4000 --check-band 2000 --metric-points 100000 --cell-mm 1.5 --quiet";

fs::path outDir(const std::string& name) {
  const fs::path dir = fs::path(RBFMUSCLE_BINARY_DIR) / "test_out/fit_warning" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(FitCommandWarnings, WarnsWithTheMeshAndFiguresWhenTheSurfaceComesOutInPieces) {
  const fs::path dir = outDir("beads");
  const test::HostResult r = test::runHost("fit " + kShapes + "box.ply --centres 30 --global-shape 0.5 -o " +
                                               (dir / "box.rbf").string() + kSmall,
                                           "fit_warning", "beads");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string prefix = "rbfmuscle: warning: " + kShapes + "box.ply: the fitted surface comes out in ";
  EXPECT_NE(r.err.find(prefix), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("pieces where the mesh has 1: Jaccard "), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(dir / "box.rbf"));
}

TEST(FitCommandWarnings, StaysQuietForASurfaceInOnePiece) {
  const fs::path dir = outDir("box");
  const test::HostResult r =
      test::runHost("fit " + kShapes + "box.ply --centres 80 -o " + (dir / "box.rbf").string() + kSmall,
                    "fit_warning", "box");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace rbfmuscle
