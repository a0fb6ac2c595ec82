// SPDX-License-Identifier: Apache-2.0
#include "dynamics/attachment.h"

#include "dynamics_test_shapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace rbfmuscle {
namespace {

TEST(Attachment, LandmarksAttachTheEndsOnly) {
  const GaussianField field = test::makeRodField();
  const Attachments a = test::makeRodAttachments(field);
  for (int k = 0; k < field.getNumCentres(); ++k) {
    const double x = field.getCentres()(0, k);
    const int expected = x < -22.0 ? 0 : (x > 22.0 ? 1 : -1);
    EXPECT_EQ(a.bone_of_centre[static_cast<size_t>(k)], expected) << "centre " << k << " at x = " << x;
  }
  EXPECT_EQ(a.countAttachedTo(0), a.countAttachedTo(1));
  EXPECT_GT(a.countAttachedTo(0), 0);
}

TEST(Attachment, LandmarkWithBadBoneNamesIt) {
  const GaussianField field = test::makeRodField();
  Attachments a = makeFreeAttachments(field.getNumCentres(), 2);
  try {
    attachByLandmarks(field, {AttachmentLandmark{0, Eigen::Vector3d::Zero(), 5.0},
                              AttachmentLandmark{2, Eigen::Vector3d::Zero(), 5.0}}, a);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("landmark 1"), std::string::npos) << e.what();
  }
}

TEST(Attachment, BlendWeightsAreNormalisedInverseDistances) {
  const GaussianField field = test::makeRodField();
  const Attachments a = test::makeRodAttachments(field);
  Eigen::Matrix3Xd p(3, 3);
  p << -25, 0, 25, 0, 0, 0, 0, 0, 0;
  const double length_mm = 2.0;
  const Eigen::MatrixXd w = calcBlendWeights(p, field.getCentres(), a, length_mm);
  ASSERT_EQ(w.rows(), 2);
  for (int j = 0; j < 3; ++j) {
    double d[2] = {1e300, 1e300};  // distance to each bone's attached set, by brute force
    for (int k = 0; k < field.getNumCentres(); ++k) {
      const int b = a.bone_of_centre[static_cast<size_t>(k)];
      if (b >= 0) d[b] = std::min(d[b], (p.col(j) - field.getCentres().col(k)).norm());
    }
    EXPECT_NEAR(w(1, j), (d[0] + length_mm) / (d[0] + d[1] + 2.0 * length_mm), 1e-14) << "point " << j;
    EXPECT_NEAR(w.col(j).sum(), 1.0, 1e-15);
  }
  EXPECT_GT(w(0, 0), 0.8);            // near bone 0
  EXPECT_NEAR(w(0, 1), 0.5, 1e-12);   // the rod's attachments are mirror-symmetric in x
  EXPECT_GT(w(1, 2), 0.8);
  // ℓ → large: equal weights.
  const Eigen::MatrixXd flat = calcBlendWeights(p, field.getCentres(), a, 1e9);
  EXPECT_NEAR(flat(0, 0), 0.5, 1e-6);
}

TEST(Attachment, BlendWeightsWithAPowerAreNormalisedInversePowersOfTheDistances) {
  const GaussianField field = test::makeRodField();
  const Attachments a = test::makeRodAttachments(field);
  const Eigen::Matrix3Xd p = Eigen::Vector3d(-10, 0, 0);
  const Eigen::MatrixXd w1 = calcBlendWeights(p, field.getCentres(), a, 1.0);
  const Eigen::MatrixXd w2 = calcBlendWeights(p, field.getCentres(), a, 1.0, 2.0);
  // With d_b + ℓ = u_b: w1_0 / w1_1 = u_1 / u_0, and w2_0 / w2_1 = (u_1 / u_0)².
  const double ratio = w1(0, 0) / w1(1, 0);
  EXPECT_NEAR(w2(0, 0) / w2(1, 0), ratio * ratio, 1e-9 * ratio * ratio);
  EXPECT_NEAR(w2.col(0).sum(), 1.0, 1e-15);
  EXPECT_THROW(calcBlendWeights(p, field.getCentres(), a, 1.0, 0.0), std::invalid_argument);
}

// Bone 0's kernels along +x, bone 1's along +y, both seen from the origin: α = 90°, and a point
// at angle φ from +x in the xy plane has t = φ / 90°.
struct RightAngle {
  Eigen::Matrix3Xd centres;
  Attachments attachments;
  RightAngle() : centres(3, 4), attachments(makeFreeAttachments(4, 2)) {
    centres << 30, 60, 0, 0,  //
        0, 0, 30, 60,         //
        0, 0, 0, 0;
    attachments.bone_of_centre = {0, 0, 1, 1};
  }
};

TEST(Attachment, JointAngleWeightsFollowTheRampOfTheAngleAtAnyDistanceFromTheJoint) {
  const RightAngle a;
  const double e = kJointBlendEndFraction, slope = 1.0 / (1.0 - e);
  for (double phi_deg : {0.0, 5.0, 18.0, 30.0, 45.0, 70.0, 85.0, 90.0}) {
    const double t = phi_deg / 90.0, u = std::min(t, 1.0 - t);
    const double h_low = u < e ? slope * u * u / (2.0 * e) : slope * (u - 0.5 * e);
    const double expected = t <= 0.5 ? h_low : 1.0 - h_low;
    const double phi = phi_deg * M_PI / 180.0;
    for (double r_mm : {5.0, 40.0, 900.0}) {
      const Eigen::Matrix3Xd p = Eigen::Vector3d(r_mm * std::cos(phi), r_mm * std::sin(phi), 0.0);
      const Eigen::MatrixXd w = calcJointAngleBlendWeights(p, a.centres, a.attachments, Eigen::Vector3d::Zero());
      EXPECT_NEAR(w(1, 0), expected, 1e-12) << phi_deg << "° at " << r_mm << " mm";
      EXPECT_NEAR(w.col(0).sum(), 1.0, 1e-15);
    }
  }
  EXPECT_NEAR(calcAttachmentAngle(a.centres, a.attachments, Eigen::Vector3d::Zero()), M_PI / 2, 1e-15);
}

TEST(Attachment, JointAngleWeightsRefuseWhatTheyCannotUse) {
  const RightAngle a;
  const Eigen::Matrix3Xd p = Eigen::Vector3d(1, 1, 0);
  Attachments one_bone = a.attachments;
  one_bone.bone_of_centre = {0, 0, -1, -1};
  EXPECT_THROW(calcJointAngleBlendWeights(p, a.centres, one_bone, Eigen::Vector3d::Zero()), std::invalid_argument);
  EXPECT_THROW(calcJointAngleBlendWeights(p, a.centres, a.attachments, Eigen::Vector3d(NAN, 0, 0)),
               std::invalid_argument);
  EXPECT_THROW(calcJointAngleBlendWeights(p, a.centres, a.attachments, Eigen::Vector3d::Zero(), 0.5),
               std::invalid_argument);
}

}  // namespace
}  // namespace rbfmuscle
