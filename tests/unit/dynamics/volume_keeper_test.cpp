#include "dynamics/volume_keeper.h"
#include "dynamics/quadrature.h"

#include <gtest/gtest.h>

#include "dynamics_test_shapes.h"

#include <cmath>

namespace rbfmuscle {
namespace {

TEST(VolumeKeeper, MeasuresASphere) {
  const GaussianField field = test::makeSphereField();
  const Quadrature q = makeQuadrature(field, QuadratureSettings{});
  const VolumeKeeper keeper(q.points_mm, q.weights_mm3(0), field, VolumeSettings{});
  EXPECT_NEAR(keeper.getRestVolume() / (4.0 / 3.0 * M_PI * 1000.0), 1.0, 0.03);
}

TEST(VolumeKeeper, RestoresTheVolumeOfAShrunkenSphereByTheOffset) {
  GaussianField field = test::makeSphereField();
  const Quadrature q = makeQuadrature(field, QuadratureSettings{});
  VolumeKeeper keeper(q.points_mm, q.weights_mm3(0), field, VolumeSettings{});
  field.setWeights(Eigen::VectorXd::Constant(1, 0.8 * 5.0 * std::exp(1.0)));  // radius 10 → 9.03 mm
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(q.points_mm.cols());
  const VolumeReport r = keeper.correct(field, q.points_mm, ones);
  EXPECT_LT(r.volume_ratio_before, 0.8);
  EXPECT_EQ(r.stop_reason, VolumeStop::kWithinTolerance) << toString(r.stop_reason);
  EXPECT_NEAR(r.volume_ratio, 1.0, 1e-3);
  EXPECT_NEAR(keeper.calcVolume(field, q.points_mm, ones), r.volume_mm3, 1e-9 * r.volume_mm3);
  EXPECT_GT(field.getOffset(), -5.0);
  EXPECT_LE(r.iterations, 20);
}

TEST(VolumeKeeper, ReportsTheOffsetBoundInsteadOfGoingPastIt) {
  GaussianField field = test::makeSphereField();
  const Quadrature q = makeQuadrature(field, QuadratureSettings{});
  VolumeSettings settings;
  settings.max_offset_change = 0.2;
  VolumeKeeper keeper(q.points_mm, q.weights_mm3(0), field, settings);
  field.setWeights(Eigen::VectorXd::Constant(1, 0.3 * 5.0 * std::exp(1.0)));
  const VolumeReport r = keeper.correct(field, q.points_mm, Eigen::VectorXd::Ones(q.points_mm.cols()));
  EXPECT_EQ(r.stop_reason, VolumeStop::kOffsetBound);
  EXPECT_DOUBLE_EQ(field.getOffset(), -4.8);
  EXPECT_TRUE(std::isfinite(r.volume_ratio));
}

}  // namespace
}  // namespace rbfmuscle
