#include "dynamics/motion_prediction.h"

#include "dynamics_test_shapes.h"
#include "support/eigen_compare.h"

#include <gtest/gtest.h>

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

TEST(MotionPrediction, OneCommonTransformMovesEveryPointByIt) {
  const Eigen::Isometry3d x = makeTransform();
  const std::vector<DualQuaternion> dqs = {toDualQuaternion(x), toDualQuaternion(x)};
  Eigen::Matrix3Xd p = Eigen::Matrix3Xd::Random(3, 20) * 40.0;
  Eigen::MatrixXd w(2, 20);
  w.row(0).setLinSpaced(0.0, 1.0);
  w.row(1) = 1.0 - w.row(0).array();
  Eigen::Matrix3Xd out;
  predictPoints(p, w, dqs, out);
  EXPECT_TRUE(test::isApprox(out, x * p, 1e-11));
}

TEST(MotionPrediction, BlendIsRigidAndInterpolatesTheEnds) {
  const Eigen::Isometry3d a = Eigen::Isometry3d::Identity();
  const Eigen::Isometry3d b = test::makeRotationAbout(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d::UnitZ(), 1.4);
  const std::vector<DualQuaternion> dqs = {toDualQuaternion(a), toDualQuaternion(b)};
  const Eigen::Isometry3d half = blendTransforms(Eigen::Vector2d(0.5, 0.5), dqs);
  // Half of a 1.4 rad turn about z through the origin: a 0.7 rad turn (a linear blend would shrink it).
  const Eigen::Isometry3d expected = test::makeRotationAbout(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 0.7);
  EXPECT_TRUE(test::isApprox(half.matrix(), expected.matrix(), 1e-12));
  EXPECT_TRUE(test::isApprox(blendTransforms(Eigen::Vector2d(0, 1), dqs).matrix(), b.matrix(), 1e-12));
}

TEST(MotionPrediction, AttachedCentresMoveExactlyWithTheirBone) {
  const GaussianField field = test::makeRodField();
  const Attachments att = test::makeRodAttachments(field);
  const Eigen::MatrixXd w = calcBlendWeights(field.getCentres(), field.getCentres(), att, 20.0);
  const Eigen::Isometry3d t1 = test::makeRotationAbout(Eigen::Vector3d(20, 0, 0), Eigen::Vector3d::UnitY(), 0.5);
  const std::vector<DualQuaternion> dqs = {toDualQuaternion(Eigen::Isometry3d::Identity()), toDualQuaternion(t1)};
  Eigen::Matrix3Xd out;
  predictCentres(field.getCentres(), att, w, dqs, out);
  for (int k = 0; k < field.getNumCentres(); ++k) {
    const Eigen::Vector3d rest = field.getCentres().col(k);
    if (att.bone_of_centre[static_cast<size_t>(k)] == 0) {
      EXPECT_EQ(out.col(k), rest) << k;
    }
    if (att.bone_of_centre[static_cast<size_t>(k)] == 1) {
      EXPECT_TRUE(test::isApprox(out.col(k), t1 * rest, 1e-12)) << k;
    }
    EXPECT_TRUE(out.col(k).allFinite());
  }
}

}  // namespace
}  // namespace rbfmuscle
