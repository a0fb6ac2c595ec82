// SPDX-License-Identifier: Apache-2.0
#include "fit/halton.h"

#include <gtest/gtest.h>

namespace rbfmuscle {
namespace {

TEST(Halton, RadicalInverseKnownValues) {
  EXPECT_DOUBLE_EQ(calcRadicalInverse(1, 2), 0.5);
  EXPECT_DOUBLE_EQ(calcRadicalInverse(2, 2), 0.25);
  EXPECT_DOUBLE_EQ(calcRadicalInverse(3, 2), 0.75);
  EXPECT_DOUBLE_EQ(calcRadicalInverse(1, 3), 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(calcRadicalInverse(5, 3), 2.0 / 3.0 + 1.0 / 9.0);  // 5 = 12 in base 3
  EXPECT_DOUBLE_EQ(calcRadicalInverse(0, 5), 0.0);
}

TEST(Halton, PointsFillTheBoxEvenly) {
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-10, 0, 5), Eigen::Vector3d(30, 20, 15));
  const Eigen::Matrix3Xd p = makeHaltonPoints(box, 20000);
  int in_octant = 0;
  for (Eigen::Index k = 0; k < p.cols(); ++k) {
    ASSERT_TRUE(box.contains(p.col(k))) << k;
    in_octant += (p.col(k).array() < box.center().array()).all();
  }
  // Low discrepancy: one octant holds 1/8 of the points to well under 1 %.
  EXPECT_NEAR(in_octant / 20000.0, 0.125, 0.002);
}

TEST(Halton, StretchesWithDifferentStartsAreDisjoint) {
  const Eigen::AlignedBox3d box(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones());
  const Eigen::Matrix3Xd a = makeHaltonPoints(box, 100, 0), b = makeHaltonPoints(box, 100, 100);
  const Eigen::Matrix3Xd both = makeHaltonPoints(box, 200, 0);
  EXPECT_TRUE(both.leftCols(100).isApprox(a, 0));
  EXPECT_TRUE(both.rightCols(100).isApprox(b, 0));
}

}  // namespace
}  // namespace rbfmuscle
