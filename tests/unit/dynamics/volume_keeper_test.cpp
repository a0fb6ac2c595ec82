#include "dynamics/volume_keeper.h"
#include "dynamics/quadrature.h"

#include <gtest/gtest.h>

#include "dynamics_test_shapes.h"

#include <cmath>

namespace rbfmuscle {
namespace {

/// Correction weights c = |λ| for every centre of `field` (all free).
Eigen::VectorXd allFree(const GaussianField& field) { return field.getWeights().cwiseAbs(); }

TEST(VolumeKeeper, MeasuresASphere) {
  const GaussianField field = test::makeSphereField();
  const Quadrature q = makeQuadrature(field, QuadratureSettings{});
  const VolumeKeeper keeper(q.points_mm, q.weights_mm3(0), field, allFree(field), VolumeSettings{});
  EXPECT_NEAR(keeper.getRestVolume() / (4.0 / 3.0 * M_PI * 1000.0), 1.0, 0.03);
}

// f = −5 + λ exp(−0.01 r²): the rest volume needs λ back at its rest value, so with c = |λ_rest|
// a sphere shrunken to λ = 0.8 λ_rest needs δ = 0.2 exactly (up to the volume tolerance).
TEST(VolumeKeeper, RestoresTheVolumeOfAShrunkenSphereThroughItsWeight) {
  GaussianField field = test::makeSphereField();
  const Quadrature q = makeQuadrature(field, QuadratureSettings{});
  VolumeKeeper keeper(q.points_mm, q.weights_mm3(0), field, allFree(field), VolumeSettings{});
  const double rest_weight = field.getWeights()(0);
  field.setWeights(Eigen::VectorXd::Constant(1, 0.8 * rest_weight));  // radius 10 → 9.03 mm
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(q.points_mm.cols());
  const VolumeReport r = keeper.correct(field, q.points_mm, ones);
  EXPECT_LT(r.volume_ratio_before, 0.8);
  EXPECT_EQ(r.stop_reason, VolumeStop::kWithinTolerance) << toString(r.stop_reason);
  EXPECT_NEAR(r.volume_ratio, 1.0, 1e-3);
  EXPECT_NEAR(keeper.calcVolume(field, q.points_mm, ones), r.volume_mm3, 1e-9 * r.volume_mm3);
  EXPECT_NEAR(r.correction, 0.2, 2e-3);
  EXPECT_NEAR(field.getWeights()(0), (0.8 + r.correction) * rest_weight, 1e-12);
  EXPECT_DOUBLE_EQ(field.getOffset(), -5.0);
  EXPECT_LE(r.iterations, 20);
  // Taking the correction out restores the weight; the next search starts from the last δ.
  keeper.removeCorrection(field);
  EXPECT_NEAR(field.getWeights()(0), 0.8 * rest_weight, 1e-12);
  EXPECT_EQ(keeper.getCorrection(), 0.0);
  const VolumeReport again = keeper.correct(field, q.points_mm, ones);
  EXPECT_NEAR(again.correction, r.correction, 1e-12);
  EXPECT_LE(again.iterations, 1);
}

TEST(VolumeKeeper, ReportsTheCorrectionBoundInsteadOfGoingPastIt) {
  GaussianField field = test::makeSphereField();
  const Quadrature q = makeQuadrature(field, QuadratureSettings{});
  VolumeSettings settings;
  settings.max_correction = 0.2;
  VolumeKeeper keeper(q.points_mm, q.weights_mm3(0), field, allFree(field), settings);
  const double rest_weight = field.getWeights()(0);
  field.setWeights(Eigen::VectorXd::Constant(1, 0.3 * rest_weight));
  const VolumeReport r = keeper.correct(field, q.points_mm, Eigen::VectorXd::Ones(q.points_mm.cols()));
  EXPECT_EQ(r.stop_reason, VolumeStop::kCorrectionBound);
  EXPECT_DOUBLE_EQ(r.correction, 0.2);
  EXPECT_NEAR(field.getWeights()(0), 0.5 * rest_weight, 1e-12);
  EXPECT_TRUE(std::isfinite(r.volume_ratio));
}

// Two spheres 60 mm apart, the second with c = 0 (attached): the correction refills the
// first and leaves the second's surface where it is (f there changes by the first's
// Gaussian tail only, φ < 1e-6).
TEST(VolumeKeeper, LeavesCentresWithoutCorrectionWeightWhereTheyAre) {
  Eigen::Matrix3Xd xi = Eigen::Matrix3Xd::Zero(3, 2);
  xi(0, 1) = 60.0;
  const double lambda = 5.0 * std::exp(1.0);
  GaussianField field(-5.0, xi, Eigen::Vector2d(lambda, lambda), Eigen::Vector2d(0.01, 0.01));
  const Quadrature q = makeQuadrature(field, QuadratureSettings{});
  VolumeKeeper keeper(q.points_mm, q.weights_mm3(0), field, Eigen::Vector2d(lambda, 0.0), VolumeSettings{});
  field.setWeights(Eigen::Vector2d(0.7 * lambda, lambda));
  const Eigen::Vector3d on_second(70.0, 0.0, 0.0);  // the second sphere's surface (radius 10 mm)
  const double before = field.calcValue(on_second);
  const VolumeReport r = keeper.correct(field, q.points_mm, Eigen::VectorXd::Ones(q.points_mm.cols()));
  EXPECT_EQ(r.stop_reason, VolumeStop::kWithinTolerance) << toString(r.stop_reason);
  EXPECT_NEAR(r.volume_ratio, 1.0, 1e-3);
  EXPECT_GT(r.correction, 0.25);
  EXPECT_DOUBLE_EQ(field.getWeights()(1), lambda);
  EXPECT_NEAR(field.calcValue(on_second), before, 1e-6);
  EXPECT_NEAR(before, 0.0, 1e-9);
}

TEST(VolumeKeeper, RejectsBadCorrectionWeights) {
  const GaussianField field = test::makeSphereField();
  const Quadrature q = makeQuadrature(field, QuadratureSettings{});
  EXPECT_THROW(VolumeKeeper(q.points_mm, q.weights_mm3(0), field, Eigen::Vector2d(1.0, 1.0), VolumeSettings{}),
               std::invalid_argument);
  EXPECT_THROW(VolumeKeeper(q.points_mm, q.weights_mm3(0), field, Eigen::VectorXd::Constant(1, -1.0), VolumeSettings{}),
               std::invalid_argument);
}

}  // namespace
}  // namespace rbfmuscle
