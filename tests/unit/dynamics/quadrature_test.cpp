// SPDX-License-Identifier: Apache-2.0
#include "dynamics/quadrature.h"

#include <gtest/gtest.h>

#include "dynamics_test_shapes.h"

#include <cmath>

namespace rbfmuscle {
namespace {

TEST(Quadrature, CoversTheBandWithAboutTheTargetCount) {
  const GaussianField field = test::makeSphereField();
  QuadratureSettings settings;
  settings.target_count = 3000;
  const Quadrature q = makeQuadrature(field, settings);
  EXPECT_GT(q.points_mm.cols(), 0.8 * settings.target_count);
  EXPECT_LT(q.points_mm.cols(), 1.2 * settings.target_count);
  // The band f > −4 is the ball λφ > 1, r < √(ln λ / α) ≈ 16.2 mm.
  const double band_radius = std::sqrt(std::log(5.0 * std::exp(1.0)) / 0.01);
  double max_r = 0.0;
  for (Eigen::Index j = 0; j < q.points_mm.cols(); ++j) {
    max_r = std::max(max_r, q.points_mm.col(j).norm());
    EXPECT_GT(field.calcValue(q.points_mm.col(j)), -settings.band_value);
  }
  EXPECT_LT(max_r, band_radius);
  EXPECT_GT(max_r, band_radius - 2.0 * q.cell_mm);
  EXPECT_DOUBLE_EQ(q.weights_mm3(0), q.cell_mm * q.cell_mm * q.cell_mm);
  // Σ w ≈ the band ball's volume.
  const double ball = 4.0 / 3.0 * M_PI * std::pow(band_radius, 3);
  EXPECT_NEAR(q.weights_mm3.sum() / ball, 1.0, 0.05);
}

TEST(Quadrature, RejectsAFarFieldInsideTheBand) {
  GaussianField field = test::makeSphereField();
  field.setOffset(-3.0);  // −b − β = −1 < 0
  EXPECT_THROW(makeQuadrature(field, QuadratureSettings{}), std::invalid_argument);
}

}  // namespace
}  // namespace rbfmuscle
