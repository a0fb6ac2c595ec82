// SPDX-License-Identifier: Apache-2.0
/// Near crumbs: bumps of f apart from the surface that a small rise of f makes islands, and
/// dips inside that a small fall makes bubbles. The finder finds their peaks and floors within
/// its margin and no others; the fit carves them, which the
/// psoas major's fit needs (four bumps within 0.5 of f = 0 beside its surface without it).
#include <gtest/gtest.h>

#include <stdexcept>

#include "fit/fit_pipeline.h"
#include "fit/near_crumbs.h"

namespace rbfmuscle {
namespace {

const Eigen::AlignedBox3d kBox(Eigen::Vector3d(-30, -30, -30), Eigen::Vector3d(50, 30, 30));

/// A ball of radius 10 about the origin (f = −10 + 20 exp(−α|x|²), α = ln 2 / 100) and a
/// narrow bump at x = 30 whose peak is `peak` (f = −10 + (10 + peak) exp(−|x − (30, 0, 0)|²/4)).
GaussianField makeBallAndBump(double peak) {
  GaussianField field(-10.0);
  field.addCentre(Eigen::Vector3d::Zero(), 20.0, std::log(2.0) / 100.0);
  field.addCentre(Eigen::Vector3d(30, 0, 0), 10.0 + peak - 20.0 * std::exp(-std::log(2.0) * 9.0), 0.25);
  return field;
}

TEST(NearCrumbs, ABumpWithinTheMarginIsFoundAtItsPeak) {
  const Eigen::Matrix3Xd peaks = findNearCrumbs(makeBallAndBump(-0.2), kBox, 1.0, 0.5);
  ASSERT_EQ(peaks.cols(), 1);
  EXPECT_LE((peaks.col(0) - Eigen::Vector3d(30, 0, 0)).norm(), 1.0);
}

TEST(NearCrumbs, ABumpBelowTheMarginIsNotAndAnIslandAlwaysIs) {
  EXPECT_EQ(findNearCrumbs(makeBallAndBump(-0.2), kBox, 1.0, 0.1).cols(), 0);
  EXPECT_EQ(findNearCrumbs(makeBallAndBump(-0.8), kBox, 1.0, 0.5).cols(), 0);
  EXPECT_EQ(findNearCrumbs(makeBallAndBump(0.3), kBox, 1.0, 0.0).cols(), 1);
  EXPECT_EQ(findNearCrumbs(makeBallAndBump(0.3), kBox, 1.0, 0.5).cols(), 1);  // the same node at every level
}

/// The ball of makeBallAndBump with a narrow dip at its centre whose floor is `pit`
/// (f = 10 + (pit − 10) exp(−|x|²/4) near it).
GaussianField makeBallAndPit(double pit) {
  GaussianField field(-10.0);
  field.addCentre(Eigen::Vector3d::Zero(), 20.0, std::log(2.0) / 100.0);
  field.addCentre(Eigen::Vector3d::Zero(), pit - 10.0, 0.25);
  return field;
}

TEST(NearCrumbs, ADipWithinTheMarginOfABubbleIsFoundAtItsFloorAndABubbleAlwaysIs) {
  // The gluteus maximus fitted with 2000 centres had a bubble of 55 mm³ 19 mm inside its surface.
  const Eigen::Matrix3Xd floors = findNearCrumbs(makeBallAndPit(0.2), kBox, 1.0, 0.5);
  ASSERT_EQ(floors.cols(), 1);
  EXPECT_LE(floors.col(0).norm(), 1.0);
  EXPECT_EQ(findNearCrumbs(makeBallAndPit(0.8), kBox, 1.0, 0.5).cols(), 0);
  EXPECT_EQ(findNearCrumbs(makeBallAndPit(-0.3), kBox, 1.0, 0.0).cols(), 1);
}

TEST(NearCrumbs, BadArgumentsAreRefused) {
  EXPECT_THROW(findNearCrumbs(makeBallAndBump(-0.2), kBox, 1.0, -0.1), std::invalid_argument);
  EXPECT_THROW(findNearCrumbs(makeBallAndBump(-0.2), kBox, 0.0, 0.5), std::invalid_argument);
}

std::string modelPath(const std::string& relative) {
  return std::string(RBFMUSCLE_SOURCE_DIR) + "/models/" + relative;
}

TEST(NearCrumbs, ThePsoasFitHasNoneWithTheDefaultsButSomeWithoutTheMarginAndTheSlope) {
  const std::string mesh = modelPath("hip/meshes/psoas_major_r.ply");
  const FitSettings defaults;
  const MeshFit fit = fitMeshFile(mesh, defaults, false);
  EXPECT_GT(fit.near_crumb_samples_added, 0);
  EXPECT_EQ(fit.near_crumbs_left, 0);
  const Eigen::AlignedBox3d box(fit.metrics.surface_M.vertices_mm.rowwise().minCoeff().transpose().array() - 20.0,
                                fit.metrics.surface_M.vertices_mm.rowwise().maxCoeff().transpose().array() + 20.0);
  EXPECT_EQ(findNearCrumbs(fit.surface.field, box, 1.0, defaults.crumb_margin_mm).cols(), 0);
  EXPECT_EQ(fit.metrics.components, 1);

  // Check points held to half their depth leave no shelf beside the surface, and so no bump
  // within the margin either; held to their side only, the fit keeps bumps the margin carves.
  FitSettings slope_only = defaults;
  slope_only.crumb_margin_mm = 0.0;
  const MeshFit sloped = fitMeshFile(mesh, slope_only, false);
  EXPECT_EQ(findNearCrumbs(sloped.surface.field, box, 1.0, defaults.crumb_margin_mm).cols(), 0);

  FitSettings side_only = defaults;
  side_only.crumb_margin_mm = 0.0;
  side_only.check_slope = 0.0;
  const MeshFit plain = fitMeshFile(mesh, side_only, false);
  EXPECT_GE(findNearCrumbs(plain.surface.field, box, 1.0, defaults.crumb_margin_mm).cols(), 2);
}

TEST(NearCrumbs, TheGluteusFitWith2000CentresHasNoBubble) {
  // Without the bubbles' floors as samples, this fit had a bubble of 55 mm³ 19 mm inside its
  // surface (2 pieces of surface, max distance 19 mm).
  FitSettings settings;
  settings.max_centres = 2000;
  const MeshFit fit = fitMeshFile(modelPath("hip/meshes/gluteus_maximus_r.ply"), settings, false);
  EXPECT_GT(fit.near_crumb_samples_added, 0);
  EXPECT_EQ(fit.near_crumbs_left, 0);
  EXPECT_EQ(fit.metrics.components, 1);
  EXPECT_LT(fit.metrics.max_distance_mm, 2.0);
}

}  // namespace
}  // namespace rbfmuscle
