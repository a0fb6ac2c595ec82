// Weight refit: the carried rest field is matched by refitting λ with the centres fixed.
#include "dynamics/weight_refit.h"

#include "dynamics_test_shapes.h"

#include <gtest/gtest.h>

namespace rbfmuscle {
namespace {

RefitSettings smallRefit() {
  RefitSettings s;
  s.sample_count = 2000;
  s.max_iterations = 200;
  s.tolerance = 1e-10;
  s.ridge = 1e-8;
  return s;
}

// At identity with the rest centres, the targets are the field's own values: λ is kept (to rounding).
TEST(WeightRefit, IdentityKeepsTheRestWeights) {
  GaussianField field = test::makeRodField();
  const Attachments a = test::makeRodAttachments(field);
  WeightRefit refit(field, a, smallRefit(), 20.0);
  const Eigen::VectorXd rest = field.getWeights();
  const WeightRefitReport r = refit.run(field, {DualQuaternion{}, DualQuaternion{}});
  EXPECT_GT(r.samples, 1000);
  EXPECT_LT(r.rms_residual_before, 1e-12);
  EXPECT_LT((field.getWeights() - rest).cwiseAbs().maxCoeff(), 1e-10);
}

// Free weights disturbed by ±20 %: the refit to the rest values at the rest samples
// brings them back (the rod's Gaussians are well separated by the samples).
TEST(WeightRefit, RecoversDisturbedWeights) {
  GaussianField field = test::makeRodField();
  const Attachments a = test::makeRodAttachments(field);
  WeightRefit refit(field, a, smallRefit(), 20.0);
  const Eigen::VectorXd rest = field.getWeights();
  Eigen::VectorXd disturbed = rest;
  for (int k = 0; k < disturbed.size(); ++k)
    if (!a.isAttached(k)) disturbed[k] *= 1.0 + 0.2 * std::cos(2.3 * k);
  field.setWeights(disturbed);
  const WeightRefitReport r = refit.run(field, {DualQuaternion{}, DualQuaternion{}});
  EXPECT_GT(r.rms_residual_before, 0.03);
  EXPECT_LT(r.rms_residual_after, 1e-4 * r.rms_residual_before);
  EXPECT_LT((field.getWeights() - rest).cwiseAbs().maxCoeff(), 1e-3);
  for (int k = 0; k < rest.size(); ++k) {
    if (a.isAttached(k)) {
      EXPECT_EQ(field.getWeights()[k], rest[k]) << k;  // attached λ kept
    }
  }
}

// Both bones moved by one rigid motion, centres moved with it: the carried field is the
// rest field moved rigidly, so the refit finds nothing to change.
TEST(WeightRefit, CommonRigidMotionKeepsTheWeights) {
  GaussianField field = test::makeRodField();
  const Attachments a = test::makeRodAttachments(field);
  WeightRefit refit(field, a, smallRefit(), 20.0);
  const Eigen::VectorXd rest = field.getWeights();
  const Eigen::Isometry3d t = test::makeRotationAbout(Eigen::Vector3d(3, -2, 1), Eigen::Vector3d(0.3, 1, 0.2), 0.7);
  field.setCentrePositions(t * field.getCentres());
  const WeightRefitReport r = refit.run(field, {toDualQuaternion(t), toDualQuaternion(t)});
  EXPECT_LT(r.rms_residual_before, 1e-9);
  EXPECT_LT((field.getWeights() - rest).cwiseAbs().maxCoeff(), 1e-8);
  EXPECT_TRUE(refit.getSamples().isApprox(t * refit.getRestSamples(), 1e-12));
}

TEST(WeightRefit, BadSettingsNameTheField) {
  const GaussianField field = test::makeRodField();
  const Attachments a = test::makeRodAttachments(field);
  RefitSettings s = smallRefit();
  s.ridge = 0.0;
  try {
    WeightRefit refit(field, a, s, 20.0);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("ridge"), std::string::npos);
  }
}

}  // namespace
}  // namespace rbfmuscle
