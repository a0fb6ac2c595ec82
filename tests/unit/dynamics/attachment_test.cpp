#include "dynamics/attachment.h"

#include "dynamics_test_shapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>

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

TEST(Attachment, ProximityUsesSupportRadius) {
  // Two "bones": single triangles far in x at each end of the rod, 8 mm beyond the last centres.
  TriangleMesh left, right;
  left.vertices_mm.resize(3, 3);
  left.vertices_mm << -38, -38, -38, -50, 50, 0, -50, -50, 50;
  left.triangles.resize(3, 1);
  left.triangles << 0, 1, 2;
  right = left;
  right.vertices_mm.row(0).setConstant(38.0);
  const MeshDistance dl(left), dr(right);
  const GaussianField field = test::makeRodField();
  // σ = 1/√0.02 ≈ 7.07 mm: the x = ±30 centres reach within 0.93 mm, the ±25 ones within 5.93 mm.
  Attachments a = makeFreeAttachments(field.getNumCentres(), 2);
  attachByProximity(field, {&dl, &dr}, 1.0, 1.0, a);
  for (int k = 0; k < field.getNumCentres(); ++k) {
    const double x = field.getCentres()(0, k);
    const int expected = x < -29.0 ? 0 : (x > 29.0 ? 1 : -1);
    EXPECT_EQ(a.bone_of_centre[static_cast<size_t>(k)], expected) << "centre " << k;
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

// A supporting bone counts its surface as attached: d_b = min(distance to its attached
// centres, distance to its surface). A plate under the rod's middle (y = −6 mm, bone 0)
// makes the middle follow bone 0 (without support it is half and half), and takes some
// weight at x = 30 mm too, 21 mm from the plate.
TEST(Attachment, SupportingBoneSurfaceCountsAsAttached) {
  TriangleMesh plate;
  plate.vertices_mm.resize(3, 3);
  plate.vertices_mm << -10, 10, 0, -6, -6, -6, -10, -10, 10;
  plate.triangles.resize(3, 1);
  plate.triangles << 0, 1, 2;
  const GaussianField field = test::makeRodField();
  Attachments a = test::makeRodAttachments(field);
  Eigen::Matrix3Xd p(3, 2);
  p << 0, 30, 0, 0, 0, 0;
  const double length_mm = 1.0;
  const Eigen::MatrixXd plain = calcBlendWeights(p, field.getCentres(), a, length_mm);
  const auto surface = std::make_shared<const MeshDistance>(plate);
  addSupport(0, surface, a);
  const Eigen::MatrixXd supported = calcBlendWeights(p, field.getCentres(), a, length_mm);
  EXPECT_NEAR(plain(0, 0), 0.5, 1e-12);
  for (int j = 0; j < 2; ++j) {
    double d[2] = {1e300, 1e300};  // distance to each bone's attached set, by brute force
    for (int k = 0; k < field.getNumCentres(); ++k) {
      const int b = a.bone_of_centre[static_cast<size_t>(k)];
      if (b >= 0) d[b] = std::min(d[b], (p.col(j) - field.getCentres().col(k)).norm());
    }
    d[0] = std::min(d[0], surface->calcUnsignedDistance(p.col(j)));
    EXPECT_NEAR(supported(0, j), (d[1] + length_mm) / (d[0] + d[1] + 2.0 * length_mm), 1e-14) << j;
  }
  EXPECT_NEAR(surface->calcUnsignedDistance(p.col(0)), 6.0, 1e-12);
  EXPECT_GT(supported(0, 0), 0.75);
  EXPECT_THROW(addSupport(2, surface, a), std::invalid_argument);
  EXPECT_THROW(addSupport(0, nullptr, a), std::invalid_argument);
}

}  // namespace
}  // namespace rbfmuscle
