#include "dynamics/local_value_change.h"

#include "dynamics_test_shapes.h"

#include <gtest/gtest.h>

#include <cmath>

namespace rbfmuscle {
namespace {

/// Every centre of `field` free (or attached), weights bounded by 10 |λ|.
WeightEditLimits limitsOf(const GaussianField& field, bool free) {
  return {std::vector<bool>(static_cast<size_t>(field.getNumCentres()), free), 10.0 * field.getWeights().cwiseAbs()};
}

// Unclamped, the minimum-norm change is exact: f(x) moves by the amount asked, and only the weights
// of centres active at x move, none across zero.
TEST(ChangeValueAt, MovesTheValueByTheAmountAskedWithoutFlippingASign) {
  GaussianField field = test::makeRodField();
  Eigen::VectorXd weights = field.getWeights();
  weights(4) = -0.8;  // one negative weight: the sign rule is checked both ways
  field.setWeights(weights);
  const Eigen::Vector3d x(-8.0, 1.0, 0.3);
  for (const double change : {0.2, -0.3}) {
    Eigen::VectorXd changed = field.getWeights();
    ActiveCentres scratch;
    ASSERT_GT(changeValueAt(field, x, change, limitsOf(field, true), changed, scratch), 0);
    GaussianField moved = field;
    moved.setWeights(changed);
    EXPECT_NEAR(moved.calcValue(x), field.calcValue(x) + change, 1e-12) << change;
    for (int k = 0; k < field.getNumCentres(); ++k) {
      EXPECT_GE(changed(k) * field.getWeights()(k), 0.0) << "centre " << k;
      const double phi = std::exp(-field.getShapes()(k) * (field.getCentres().col(k) - x).squaredNorm());
      if (changed(k) != field.getWeights()(k)) EXPECT_GE(phi, field.getCutoff()) << "centre " << k << " is not active at x";
    }
  }
}

// Free centres carry the change; attached ones only where no free one is active.
TEST(ChangeValueAt, AttachedCentresMoveOnlyWhereNoFreeOneIs) {
  const GaussianField field = test::makeRodField();
  WeightEditLimits limits = limitsOf(field, true);
  for (int k = 0; k < field.getNumCentres(); k += 2) limits.free_mask[static_cast<size_t>(k)] = false;
  Eigen::VectorXd changed = field.getWeights();
  ActiveCentres scratch;
  changeValueAt(field, Eigen::Vector3d(0.0, 0.0, 0.0), 0.1, limits, changed, scratch);
  for (int k = 0; k < field.getNumCentres(); k += 2) EXPECT_EQ(changed(k), field.getWeights()(k)) << "attached " << k;
  EXPECT_NE(changed, field.getWeights());
  const WeightEditLimits all_attached = limitsOf(field, false);
  changed = field.getWeights();
  EXPECT_GT(changeValueAt(field, Eigen::Vector3d(0.0, 0.0, 0.0), 0.1, all_attached, changed, scratch), 0);
}

// A weight stops at its limit, so the change falls short rather than growing a weight without bound.
TEST(ChangeValueAt, AWeightStopsAtItsLimit) {
  const GaussianField field = test::makeSphereField();
  const WeightEditLimits limits{{true}, Eigen::VectorXd::Constant(1, 1.1 * field.getWeights()(0))};
  Eigen::VectorXd changed = field.getWeights();
  ActiveCentres scratch;
  EXPECT_EQ(changeValueAt(field, Eigen::Vector3d::Zero(), 100.0, limits, changed, scratch), 1);
  EXPECT_DOUBLE_EQ(changed(0), 1.1 * field.getWeights()(0));
  EXPECT_EQ(changeValueAt(field, Eigen::Vector3d(500.0, 0.0, 0.0), 1.0, limits, changed, scratch), 0) << "nothing active there";
}

}  // namespace
}  // namespace rbfmuscle
