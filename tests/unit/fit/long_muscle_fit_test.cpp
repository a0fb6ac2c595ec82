// SPDX-License-Identifier: Apache-2.0
/// Long, slender muscles fit in one piece with the default settings; a fit that comes out in
/// pieces says so. The psoas major is the real case: its folds turned the samples' pseudo-
/// normal signs over in whole cones (17 pieces, surface up to 95 mm off, before the fix).
#include <gtest/gtest.h>

#include <filesystem>

#include "fit/fit_pipeline.h"
#include "fit/sample_set.h"
#include "fit/surface_cache.h"
#include "geometry/mesh_distance.h"
#include "geometry/mesh_io.h"
#include "geometry/solid_mesh.h"
#include "geometry/winding_number.h"
#include "unit/fit/tube_meshes.h"

namespace rbfmuscle {
namespace {

namespace fs = std::filesystem;

std::string modelPath(const std::string& relative) {
  return std::string(RBFMUSCLE_SOURCE_DIR) + "/models/" + relative;
}

/// Writes `mesh` as NAME.ply in a fresh folder of the build tree and returns its path.
std::string writeTestMesh(const TriangleMesh& mesh, const std::string& name) {
  const fs::path dir = fs::path(RBFMUSCLE_BINARY_DIR) / "test_tmp" / "fit" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string path = (dir / (name + ".ply")).string();
  writePly(path, mesh);
  return path;
}

void expectOneCleanPiece(const MeshFit& fit) {
  EXPECT_EQ(fit.mesh_components, 1);
  EXPECT_EQ(fit.metrics.components, 1);
  EXPECT_EQ(fit.metrics.clipped_nodes, 0);
  EXPECT_EQ(fit.metrics.boundary_edges, 0);
  EXPECT_TRUE(fit.warnings.empty()) << fit.warnings.front();
}

TEST(LongThinShapes, CapsuleOf200By15MmFitsInOnePieceWithTheDefaults) {
  const MeshFit fit = fitMeshFile(writeTestMesh(test::makeCapsule(200.0, 15.0), "capsule"), FitSettings{}, false);
  expectOneCleanPiece(fit);
  EXPECT_GT(fit.metrics.jaccard, 0.95);
  EXPECT_LT(fit.metrics.mean_distance_mm, 0.5);
  EXPECT_LT(fit.metrics.max_distance_mm, 2.0);
  EXPECT_NEAR(fit.metrics.volume_ratio, 1.0, 0.02);
}

TEST(LongThinShapes, TubeBentThroughThreeQuartersOfATurnFitsInOnePieceWithTheDefaults) {
  // 12 mm radius on a 60 mm arc: the inside of the bend is a concave pocket.
  const MeshFit fit = fitMeshFile(writeTestMesh(test::makeBentTube(60.0, 1.5 * M_PI, 12.0), "bent_tube"),
                                  FitSettings{}, false);
  expectOneCleanPiece(fit);
  EXPECT_GT(fit.metrics.jaccard, 0.95);
  EXPECT_LT(fit.metrics.mean_distance_mm, 0.5);
}

TEST(PsoasMajor, SamplesTakeTheirSideFromTheWindingNumberNotFromFoldedPseudoNormals) {
  TriangleMesh mesh = loadSolidMesh(modelPath("hip/meshes/psoas_major_r.ply"));
  const MeshDistance distance(mesh);
  const WindingNumber winding(mesh);
  const SampleSet samples = buildSamples(mesh, distance, winding, FitSettings{});
  EXPECT_GT(samples.resigned_samples, 100) << "the folds of the psoas turn ~200 pseudo-normal signs";
  int checked = 0;
  for (int i = 0; i < samples.getNumSamples(); i += 7) {
    if (std::abs(samples.signed_distance_mm[i]) < 0.05) continue;  // on the surface: either side
    const double w = winding.calcExactWindingNumber(samples.points_mm.col(i));
    ASSERT_EQ(samples.signed_distance_mm[i] < 0, w > 0.5)
        << "sample " << i << " s " << samples.signed_distance_mm[i] << " w " << w;
    ++checked;
  }
  EXPECT_GT(checked, 5000);
  for (int i = 0; i < samples.getNumCheckPoints(); i += 50)
    ASSERT_EQ(samples.check_signed_distance_mm[i] < 0, winding.isInside(samples.check_points_mm.col(i))) << i;
}

TEST(PsoasMajor, FitsInOnePieceWithTheDefaultsAnd300Centres) {
  FitSettings settings;
  settings.max_centres = 300;
  const MeshFit fit = fitMeshFile(modelPath("hip/meshes/psoas_major_r.ply"), settings, false);
  expectOneCleanPiece(fit);
  EXPECT_GT(fit.metrics.jaccard, 0.88);
  EXPECT_LT(fit.metrics.max_distance_mm, 10.0);
  EXPECT_NEAR(fit.metrics.volume_ratio, 1.0, 0.05);
}

/// Narrow Gaussians far too few for the box: the surface falls apart into beads.
FitSettings beadSettings() {
  FitSettings s;
  s.max_centres = 30;
  s.global_shape_per_mm2 = 0.5;
  s.halton_samples = 4000;
  s.check_band_samples = 2000;
  s.metric_points = 100000;
  s.surface_cell_mm = 1.5;
  return s;
}

TEST(FitWarnings, AFitInSeveralPiecesIsReportedWithTheMeshAndItsFigures) {
  const std::string box = modelPath("shapes/box.ply");
  const MeshFit fit = fitMeshFile(box, beadSettings(), false);
  ASSERT_GT(fit.metrics.components, 1);
  ASSERT_EQ(fit.warnings.size(), 1u);
  const std::string& w = fit.warnings.front();
  EXPECT_NE(w.find(box), std::string::npos) << w;
  EXPECT_NE(w.find(std::to_string(fit.metrics.components) + " pieces where the mesh has 1"), std::string::npos) << w;
  for (const char* figure : {"Jaccard", "mean / p95 / max distance", "volume ratio"})
    EXPECT_NE(w.find(figure), std::string::npos) << figure << " in " << w;
}

TEST(FitWarnings, ASurfaceCutByTheBoxIsReported) {
  FitMetrics m;
  m.components = 1;
  m.clipped_nodes = 1282;
  const std::vector<std::string> w = describeSuspectFit(m, 1, "psoas_major_r.ply");
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("psoas_major_r.ply: the fitted surface runs into the fitting box (1282 grid nodes"),
            std::string::npos) << w[0];
  m.clipped_nodes = 0;
  EXPECT_TRUE(describeSuspectFit(m, 1, "psoas_major_r.ply").empty());
  m.components = 2;  // a mesh of two pieces may fit as two
  EXPECT_TRUE(describeSuspectFit(m, 2, "two.ply").empty());
}

TEST(FitWarnings, SurfaceCacheWarnsWhenItsFitComesOutInSeveralPieces) {
  const std::string box = modelPath("shapes/box.ply");
  SurfaceOrigin origin = SurfaceOrigin::kCache;
  testing::internal::CaptureStderr();
  const RbfSurface surface = loadOrFitSurface(box, "", beadSettings(), origin);
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(origin, SurfaceOrigin::kFitted);
  EXPECT_EQ(surface.field.getNumCentres(), 30);
  EXPECT_NE(err.find("rbfmuscle: warning: " + box + ": the fitted surface comes out in"), std::string::npos) << err;
}

}  // namespace
}  // namespace rbfmuscle
