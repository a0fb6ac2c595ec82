// SPDX-License-Identifier: Apache-2.0
// DeformedField: derivatives against finite differences, the rest field, the frame limits,
// and the two evaluation paths agreeing bitwise.
#include "rbf/deformed_field.h"
#include "rbf/neighbour_lists.h"
#include "rbf_test_fields.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <random>

namespace rbfmuscle {
namespace {

/// A random field whose kernels are moved and given random frames near the identity.
DeformedField makeDeformed(std::mt19937& rng, double cutoff = 1e-4) {
  const GaussianField rest = test::makeRandomField(rng, 40, 0.02, 0.3, 12.0, 1e-8);
  DeformedField field(rest, cutoff);
  std::normal_distribution<double> noise(0.0, 0.3);
  std::vector<Eigen::Matrix3d> frames(40);
  Eigen::Matrix3Xd centres = rest.getCentres();
  for (int k = 0; k < 40; ++k) {
    Eigen::Matrix3d f = Eigen::Matrix3d::Identity();
    for (int i = 0; i < 9; ++i) f(i / 3, i % 3) += noise(rng);
    frames[static_cast<size_t>(k)] = f;
    centres.col(k) += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
  }
  field.setKernels(centres, frames);
  return field;
}

TEST(DeformedField, AtRestEqualsTheFittedFieldWithTheSameCutoff) {
  std::mt19937 rng(3);
  const GaussianField rest = test::makeRandomField(rng, 50, 0.02, 0.3, 12.0, 1e-4);
  const DeformedField field(rest, 1e-4);
  std::uniform_real_distribution<double> pos(-15.0, 15.0);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d p(pos(rng), pos(rng), pos(rng));
    EXPECT_NEAR(field.calcValue(p), rest.calcValue(p), 1e-12);
    EXPECT_LT((field.calcGradient(p) - rest.calcGradient(p)).norm(), 1e-12);
    EXPECT_NEAR(field.calcMeanCurvature(p), rest.calcMeanCurvature(p), 1e-12);
  }
}

TEST(DeformedField, GradientAndCurvatureMatchFiniteDifferences) {
  std::mt19937 rng(5);
  // No cut-off in reach of the differences: ε tiny.
  const DeformedField field = makeDeformed(rng, 1e-300);
  std::uniform_real_distribution<double> pos(-10.0, 10.0);
  const double h = 1e-4;
  for (int i = 0; i < 50; ++i) {
    const Eigen::Vector3d p(pos(rng), pos(rng), pos(rng));
    const Eigen::MatrixXd fd = test::centralDifference(
        [&](const Eigen::Vector3d& x) { return Eigen::VectorXd::Constant(1, field.calcValue(x)); }, p, h);
    EXPECT_LT((field.calcGradient(p) - fd.transpose()).norm(), 1e-6 * (1.0 + fd.norm())) << "point " << i;
    // κ = ∇²f / 3 against the trace of the gradient's differences.
    const Eigen::MatrixXd hessian = test::centralDifference(
        [&](const Eigen::Vector3d& x) { return Eigen::VectorXd(field.calcGradient(x)); }, p, h);
    EXPECT_NEAR(field.calcMeanCurvature(p), hessian.trace() / 3.0, 1e-5 * (1.0 + hessian.norm())) << "point " << i;
  }
}

TEST(DeformedField, AKernelStretchedByItsFrameStretchesTheField) {
  // One kernel, frame diag(2, 1, 1): φ(x) = exp(−α ((x/2)² + y² + z²)).
  const GaussianField one(0.0, Eigen::Matrix3Xd::Zero(3, 1), Eigen::VectorXd::Ones(1), Eigen::VectorXd::Constant(1, 0.1));
  DeformedField field(one, 1e-12);
  field.setKernels(Eigen::Matrix3Xd::Zero(3, 1), {Eigen::Vector3d(2.0, 1.0, 1.0).asDiagonal()});
  EXPECT_NEAR(field.calcValue(Eigen::Vector3d(4.0, 0, 0)), std::exp(-0.1 * 4.0), 1e-14);
  EXPECT_NEAR(field.calcValue(Eigen::Vector3d(0, 2.0, 0)), std::exp(-0.1 * 4.0), 1e-14);
}

TEST(DeformedField, FoldedOrSingularFramesStayFiniteAndAreClamped) {
  const GaussianField one(0.0, Eigen::Matrix3Xd::Zero(3, 2), Eigen::VectorXd::Ones(2), Eigen::VectorXd::Constant(2, 0.1));
  DeformedField field(one);
  Eigen::Matrix3d singular = Eigen::Matrix3d::Identity();
  singular(2, 2) = 0.0;  // det F = 0: a fold
  Eigen::Matrix3d folded = Eigen::Matrix3d::Identity();
  folded(0, 0) = -1e-9;  // det F < 0
  field.setKernels(Eigen::Matrix3Xd::Zero(3, 2), {singular, folded});
  EXPECT_EQ(field.countClampedFrames(), 2);
  for (double z : {0.0, 0.05, 1.0, 5.0}) {
    const FieldSample s = field.calcSample(Eigen::Vector3d(0.3, 0.2, z));
    EXPECT_TRUE(std::isfinite(s.value) && s.gradient.allFinite()) << "z " << z;
    EXPECT_TRUE(std::isfinite(field.calcMeanCurvature(Eigen::Vector3d(0.3, 0.2, z))));
  }
  // The singular kernel is as thin as min_stretch allows: A_zz = α / 0.1².
  EXPECT_NEAR(field.getKernels()[0].a_zz, 0.1 / (0.1 * 0.1), 1e-9);
}

TEST(DeformedField, ListAndGeneralSearchGiveBitwiseEqualValuesWhenTheListHoldsTheActiveKernels) {
  std::mt19937 rng(11);
  const DeformedField field = makeDeformed(rng);
  std::uniform_real_distribution<double> pos(-12.0, 12.0);
  std::vector<int> active;
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector3d p(pos(rng), pos(rng), pos(rng));
    field.findActiveKernels(p, active);
    const FieldSample listed = field.calcSampleAmong(p, active.data(), static_cast<int>(active.size()));
    const FieldSample general = field.calcSample(p);
    EXPECT_EQ(listed.value, general.value);
    EXPECT_EQ(listed.gradient, general.gradient);
  }
}

TEST(NeighbourLists, RestListsHoldEveryKernelActiveAfterAMildAffineDeformation) {
  std::mt19937 rng(13);
  const GaussianField rest_fit = test::makeRandomField(rng, 60, 0.02, 0.3, 12.0, 1e-4);
  const DeformedField rest(rest_fit);
  std::uniform_real_distribution<double> pos(-12.0, 12.0);
  Eigen::Matrix3Xd points(3, 200);
  for (int j = 0; j < 200; ++j) points.col(j) = Eigen::Vector3d(pos(rng), pos(rng), pos(rng));
  const NeighbourLists lists = findMaterialNeighbours(rest, points);
  // Carry kernels and points by one affine map with 30 % stretch and a rotation.
  Eigen::Matrix3d a = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix() *
                      Eigen::Vector3d(1.3, 0.8, 1.0).asDiagonal();
  DeformedField moved = rest;
  moved.setKernels(a * rest.getCentres(), std::vector<Eigen::Matrix3d>(60, a));
  std::vector<int> active;
  for (int j = 0; j < 200; ++j) {
    const Eigen::Vector3d y = a * points.col(j);
    moved.findActiveKernels(y, active);
    for (int k : active)
      EXPECT_TRUE(std::binary_search(lists.begin(j), lists.begin(j) + lists.count(j), k)) << "point " << j << " kernel " << k;
    EXPECT_EQ(moved.calcValueAmong(y, lists.begin(j), lists.count(j)), moved.calcValue(y));
  }
}

TEST(DeformedField, BadInputIsRefusedNamingTheKernel) {
  const GaussianField one(0.0, Eigen::Matrix3Xd::Zero(3, 1), Eigen::VectorXd::Ones(1), Eigen::VectorXd::Constant(1, 0.1));
  DeformedField field(one);
  Eigen::Matrix3Xd bad = Eigen::Matrix3Xd::Zero(3, 1);
  bad(0, 0) = std::nan("");
  try {
    field.setKernels(bad, {Eigen::Matrix3d::Identity()});
    FAIL() << "expected an exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("kernel 0"), std::string::npos) << e.what();
  }
  EXPECT_THROW(DeformedField(one, 0.0), std::invalid_argument);
  EXPECT_THROW(field.setKernels(Eigen::Matrix3Xd::Zero(3, 2), {}), std::invalid_argument);
}

}  // namespace
}  // namespace rbfmuscle
