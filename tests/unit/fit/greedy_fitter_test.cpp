// SPDX-License-Identifier: Apache-2.0
/// Fits small shapes end to end (samples → greedy → metrics) and checks the
/// figures, the stop reasons, determinism and the worst case (tetrahedron).
#include "fit/fit_pipeline.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "geometry/mesh_error.h"

namespace rbfmuscle {
namespace {

std::string shapePath(const std::string& name) {
  return std::string(RBFMUSCLE_SOURCE_DIR) + "/models/shapes/" + name + ".ply";
}

/// Settings small enough for a unit test (a few seconds).
FitSettings smallSettings(int centres) {
  FitSettings s;
  s.max_centres = centres;
  s.halton_samples = 6000;
  s.metric_points = 100000;
  s.surface_cell_mm = 1.5;
  return s;
}

void expectFiniteField(const GaussianField& field) {
  EXPECT_TRUE(field.getCentres().allFinite());
  EXPECT_TRUE(field.getWeights().allFinite());
  EXPECT_TRUE((field.getShapes().array() > 0).all());
}

TEST(GreedyFitter, BoxIsFittedCloselyAndClosed) {
  const MeshFit fit = fitMeshFile(shapePath("box"), smallSettings(150), false);
  const FitMetrics& m = fit.metrics;
  EXPECT_EQ(fit.surface.field.getNumCentres(), 150);
  EXPECT_EQ(fit.stop_reason, "centre budget");
  EXPECT_GT(m.jaccard, 0.93);
  EXPECT_NEAR(m.volume_ratio, 1.0, 0.03);
  EXPECT_LT(m.mean_distance_mm, 1.5);
  EXPECT_EQ(m.components, 1);
  EXPECT_EQ(m.boundary_edges, 0);
  EXPECT_EQ(m.clipped_nodes, 0);
  expectFiniteField(fit.surface.field);
  // The muscle frame M is centred on the mesh box (box.ply spans y ∈ [10, 90]).
  EXPECT_NEAR(fit.surface.frame_offset_mm.y(), 50.0, 1e-9);
}

TEST(GreedyFitter, MoreCentresFitBetter) {
  const MeshFit coarse = fitMeshFile(shapePath("rod"), smallSettings(20), false);
  const MeshFit fine = fitMeshFile(shapePath("rod"), smallSettings(200), false);
  EXPECT_LT(fine.metrics.metric, coarse.metrics.metric);
  EXPECT_LT(fine.metrics.mean_distance_mm, coarse.metrics.mean_distance_mm);
  EXPECT_GT(fine.metrics.jaccard, 0.9);
}

TEST(GreedyFitter, IsDeterministic) {
  const MeshFit a = fitMeshFile(shapePath("block"), smallSettings(40), false);
  const MeshFit b = fitMeshFile(shapePath("block"), smallSettings(40), false);
  EXPECT_EQ(a.surface.field.getCentres(), b.surface.field.getCentres());
  EXPECT_EQ(a.surface.field.getWeights(), b.surface.field.getWeights());
  EXPECT_EQ(a.surface.field.getShapes(), b.surface.field.getShapes());
}

TEST(GreedyFitter, StopsAtTheTolerance) {
  FitSettings s = smallSettings(400);
  s.tolerance_mm = 1.0;
  const MeshFit fit = fitMeshFile(shapePath("box"), s, false);
  EXPECT_EQ(fit.stop_reason, "tolerance");
  EXPECT_LT(fit.surface.field.getNumCentres(), 400);
}

TEST(GreedyFitter, GlobalShapeUsesOneShape) {
  FitSettings s = smallSettings(60);
  s.global_shape_per_mm2 = 0.01;
  const MeshFit fit = fitMeshFile(shapePath("box"), s, false);
  EXPECT_TRUE((fit.surface.field.getShapes().array() == 0.01).all());
}

TEST(GreedyFitter, TetrahedronGivesHonestFiniteFigures) {
  // Sharp edges and corners: the worst case for Gaussians. No NaN, no crash,
  // and the figures say the fit is imperfect rather than hide it.
  FitSettings s = smallSettings(200);
  s.surface_cell_mm = 0.02;  // the tetrahedron is about 1 mm across
  s.clamp_mm = 0.1;
  s.normal_offset_mm = 0.02;
  s.shapes_per_mm2 = {5, 10, 20, 50, 100, 200, 500, 1000};
  const MeshFit fit = fitMeshFile(shapePath("tetrahedron"), s, false);
  expectFiniteField(fit.surface.field);
  const FitMetrics& m = fit.metrics;
  for (double v : {m.jaccard, m.mean_distance_mm, m.max_distance_mm, m.volume_ratio, m.metric})
    EXPECT_TRUE(std::isfinite(v));
  EXPECT_GT(m.jaccard, 0.5);
  EXPECT_LT(m.jaccard, 1.0);
  EXPECT_GT(m.max_distance_mm, 0.0);
}

TEST(GreedyFitter, BadMeshIsRefusedWithItsName) {
  try {
    fitMeshFile(shapePath("no_such_shape"), smallSettings(10), false);
    FAIL() << "no error";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_shape.ply"), std::string::npos) << e.what();
  }
}

/// The message of the std::invalid_argument a fit of the block with `settings` throws.
std::string fitError(const FitSettings& settings) {
  try {
    fitMeshFile(shapePath("block"), settings, false);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}

TEST(GreedyFitter, SettingsThatOverflowOrLeaveNothingToFitAreRefused) {
  FitSettings s = smallSettings(5);
  s.clamp_mm = 1e300;  // the targets' squares overflowed: NaN residuals, then a crash sorting them
  EXPECT_NE(fitError(s).find("clamp 1e+300 mm, expected > 0 and ≤ 10000 mm"), std::string::npos) << fitError(s);
  s = smallSettings(5);
  s.normal_offset_mm = 20.0;
  EXPECT_NE(fitError(s).find("normal offset 20 mm, expected > 0 and at most the clamp (10 mm)"), std::string::npos);
  s = smallSettings(5);
  s.tolerance_mm = -1.0;
  EXPECT_NE(fitError(s).find("tolerance -1 mm, expected ≥ 0"), std::string::npos);
  // Targets of 1e-300 mm: no candidate reduces the error, and the refit of no centre crashed.
  s = smallSettings(5);
  s.clamp_mm = s.normal_offset_mm = 1e-300;
  EXPECT_NE(fitError(s).find("no centre reduces the error"), std::string::npos) << fitError(s);
}

TEST(GreedyFitter, CellTooFineForTheMeasureIsRefusedBeforeTheFit) {
  FitSettings s = smallSettings(5);
  s.surface_cell_mm = 0.05;
  try {
    fitMeshFile(shapePath("block"), s, false);
    FAIL() << "no error";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("block.ply: a surface cell of 0.05 mm takes a grid of 741×1441×1441 nodes"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace rbfmuscle
