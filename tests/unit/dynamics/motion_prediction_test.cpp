// SPDX-License-Identifier: Apache-2.0
#include "dynamics/motion_prediction.h"

#include "dynamics_test_shapes.h"
#include "support/eigen_compare.h"

#include <gtest/gtest.h>

#include <cmath>

namespace rbfmuscle {
namespace {

Eigen::Isometry3d makeTransform() {
  Eigen::Isometry3d x = Eigen::Isometry3d::Identity();
  x.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, -0.5).normalized()).toRotationMatrix();
  x.translation() = Eigen::Vector3d(12.0, -7.0, 3.5);
  return x;
}

TEST(MotionPrediction, DualQuaternionRoundTrip) {
  const Eigen::Isometry3d x = makeTransform();
  EXPECT_TRUE(test::isApprox(toIsometry(toDualQuaternion(x)).matrix(), x.matrix(), 1e-13));
}

/// The isometry the blend applies with weights w: its action on the origin and the unit axes.
Eigen::Isometry3d blendAsIsometry(const Eigen::Vector2d& w, const std::vector<DualQuaternion>& dqs) {
  Eigen::Isometry3d x = Eigen::Isometry3d::Identity();
  x.translation() = applyBlend(w.data(), dqs, Eigen::Vector3d::Zero());
  for (int i = 0; i < 3; ++i) x.linear().col(i) = applyBlend(w.data(), dqs, Eigen::Vector3d::Unit(i)) - x.translation();
  return x;
}

TEST(MotionPrediction, OneCommonTransformMovesEveryPointByIt) {
  const Eigen::Isometry3d x = makeTransform();
  const std::vector<DualQuaternion> dqs = {toDualQuaternion(x), toDualQuaternion(x)};
  const Eigen::Matrix3Xd p = Eigen::Matrix3Xd::Random(3, 20) * 40.0;
  for (int j = 0; j < 20; ++j) {
    const Eigen::Vector2d w(j / 19.0, 1.0 - j / 19.0);
    EXPECT_TRUE(test::isApprox(applyBlend(w.data(), dqs, p.col(j)), x * Eigen::Vector3d(p.col(j)), 1e-11)) << j;
  }
}

TEST(MotionPrediction, BlendIsRigidAndInterpolatesTheEnds) {
  const Eigen::Isometry3d a = Eigen::Isometry3d::Identity();
  const Eigen::Isometry3d b = test::makeRotationAbout(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d::UnitZ(), 1.4);
  const std::vector<DualQuaternion> dqs = {toDualQuaternion(a), toDualQuaternion(b)};
  const Eigen::Isometry3d half = blendAsIsometry(Eigen::Vector2d(0.5, 0.5), dqs);
  // Half of a 1.4 rad turn about z through the origin: a 0.7 rad turn (a linear blend would shrink it).
  const Eigen::Isometry3d expected = test::makeRotationAbout(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 0.7);
  EXPECT_TRUE(test::isApprox(half.matrix(), expected.matrix(), 1e-12));
  EXPECT_TRUE(test::isApprox(blendAsIsometry(Eigen::Vector2d(0, 1), dqs).matrix(), b.matrix(), 1e-12));
}

TEST(MotionPrediction, LinearBlendPutsThePointOnTheChordOfItsPlacesOnTheBones) {
  const std::vector<Eigen::Isometry3d> motions = {
      Eigen::Isometry3d::Identity(), test::makeRotationAbout(Eigen::Vector3d(0, -30, 0), Eigen::Vector3d::UnitZ(), 1.4)};
  const Eigen::Vector3d p(10, 20, 5);
  const Eigen::Vector3d on_1 = motions[1] * p;
  const double weights[2] = {0.25, 0.75};
  EXPECT_TRUE(test::isApprox(applyLinearBlend(weights, motions, p), 0.25 * p + 0.75 * on_1, 1e-12));
  // Half-way, at cos(0.7) of the distance from the joint's axis, where the dual-quaternion blend keeps it.
  const double half[2] = {0.5, 0.5};
  const Eigen::Vector3d radial = Eigen::Vector3d(10, 50, 0);
  EXPECT_NEAR((applyLinearBlend(half, motions, p) - Eigen::Vector3d(0, -30, 5)).norm(), std::cos(0.7) * radial.norm(), 1e-9);
  const std::vector<DualQuaternion> dqs = {toDualQuaternion(motions[0]), toDualQuaternion(motions[1])};
  EXPECT_NEAR((applyBlend(half, dqs, p) - Eigen::Vector3d(0, -30, 5)).norm(), radial.norm(), 1e-9);
}

}  // namespace
}  // namespace rbfmuscle
