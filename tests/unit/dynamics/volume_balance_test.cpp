// SPDX-License-Identifier: Apache-2.0
// VolumeBalance: a shrunken muscle gets its volume back through the free weights, and a
// bone taking part of the muscle away counts.
#include "dynamics/quadrature.h"
#include "dynamics/volume_balance.h"
#include "dynamics_test_shapes.h"

#include <gtest/gtest.h>

namespace rbfmuscle {
namespace {

TEST(VolumeBalance, RestoresTheRestVolumeOfAShrunkenRod) {
  const GaussianField fit = test::makeRodField();
  DeformedField rest(fit);
  QuadratureSettings qs;
  qs.target_count = 6000;
  const Quadrature q = makeQuadrature(fit, qs);
  const NeighbourLists lists = findMaterialNeighbours(rest, q.points_mm);
  std::vector<bool> free_mask(static_cast<size_t>(fit.getNumCentres()), true);
  const Eigen::VectorXd far = Eigen::VectorXd::Constant(q.points_mm.cols(), std::numeric_limits<double>::infinity());
  VolumeBalance balance(rest.getWeights(), free_mask, q.weights_mm3[0], q.cell_mm);
  balance.setRest(rest, q.points_mm, lists, far);
  // Shrink every kernel to 90 % across y and z: the volume drops; the balance brings it back.
  DeformedField field = rest;
  field.setKernels(rest.getCentres(), std::vector<Eigen::Matrix3d>(static_cast<size_t>(field.getNumKernels()),
                                                                   Eigen::Vector3d(1.0, 0.9, 0.9).asDiagonal()));
  const BalanceReport report = balance.balance(field, q.points_mm, lists, Eigen::VectorXd::Ones(q.points_mm.cols()), far);
  EXPECT_LT(report.ratio_before, 0.95);
  EXPECT_NEAR(report.ratio, 1.0, 1e-3);
  EXPECT_EQ(report.stop, BalanceStop::kWithinTolerance);
  EXPECT_GT(report.correction, 0.0);
}

TEST(VolumeBalance, TheBonesShareOfTheMuscleIsNotItsVolume) {
  const GaussianField fit = test::makeRodField();
  DeformedField rest(fit);
  const Quadrature q = makeQuadrature(fit, QuadratureSettings{});
  const NeighbourLists lists = findMaterialNeighbours(rest, q.points_mm);
  std::vector<bool> free_mask(static_cast<size_t>(fit.getNumCentres()), true);
  BalanceSettings measure;
  measure.enabled = false;
  VolumeBalance balance(rest.getWeights(), free_mask, q.weights_mm3[0], q.cell_mm, measure);
  const Eigen::VectorXd far = Eigen::VectorXd::Constant(q.points_mm.cols(), std::numeric_limits<double>::infinity());
  balance.setRest(rest, q.points_mm, lists, far);
  // A bone filling x > 0: s = −x there.
  Eigen::VectorXd clearance = far;
  for (Eigen::Index j = 0; j < q.points_mm.cols(); ++j) clearance[j] = -q.points_mm(0, j);
  DeformedField field = rest;
  const BalanceReport report = balance.balance(field, q.points_mm, lists, Eigen::VectorXd::Ones(q.points_mm.cols()), clearance);
  EXPECT_NEAR(report.ratio, 0.5, 0.05) << "half of the rod lies in the bone";
  EXPECT_EQ(report.stop, BalanceStop::kDisabled);
}

}  // namespace
}  // namespace rbfmuscle
