// SPDX-License-Identifier: Apache-2.0
// CurvatureObjective: zero at rest, gradient against finite differences with deformed kernels.
#include "dynamics/curvature_objective.h"
#include "dynamics_test_shapes.h"

#include <gtest/gtest.h>

#include <random>

namespace rbfmuscle {
namespace {

struct QuadratureSetup {
  GaussianField fit = test::makeRodField();
  DeformedField rest{fit, 1e-300};
  Eigen::Matrix3Xd points;
  NeighbourLists lists;
  std::vector<bool> free_mask;
  QuadratureSetup() {
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> x(-35, 35), yz(-6, 6);
    points.resize(3, 150);
    for (int j = 0; j < 150; ++j) points.col(j) = Eigen::Vector3d(x(rng), yz(rng), yz(rng));
    lists = findMaterialNeighbours(rest, points);
    free_mask.assign(static_cast<size_t>(fit.getNumCentres()), true);
    free_mask[0] = free_mask[5] = false;
  }
  CurvatureObjective make(double rho) const {
    return CurvatureObjective(Eigen::VectorXd::Constant(150, 2.0), CurvatureObjective::calcCurvatures(rest, points, lists),
                              lists, free_mask, rho);
  }
};

TEST(CurvatureObjective, IsZeroForTheRestField) {
  const QuadratureSetup s;
  const CurvatureObjective objective = s.make(0.1);
  Eigen::Matrix3Xd gradient;
  EXPECT_EQ(objective.evaluate(s.rest, s.points, s.rest.getCentres(), &gradient), 0.0);
  EXPECT_EQ(gradient.norm(), 0.0);
}

TEST(CurvatureObjective, GradientMatchesFiniteDifferencesForDeformedKernels) {
  const QuadratureSetup s;
  const CurvatureObjective objective = s.make(0.1);
  DeformedField field = s.rest;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.2);
  std::vector<Eigen::Matrix3d> frames(static_cast<size_t>(field.getNumKernels()), Eigen::Matrix3d::Identity());
  Eigen::Matrix3Xd centres = field.getCentres();
  for (int k = 0; k < field.getNumKernels(); ++k) {
    for (int i = 0; i < 9; ++i) frames[static_cast<size_t>(k)](i / 3, i % 3) += noise(rng);
    centres.col(k) += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
  }
  field.setKernels(centres, frames);
  const Eigen::Matrix3Xd anchors = s.rest.getCentres();
  Eigen::Matrix3Xd gradient;
  objective.evaluate(field, s.points, anchors, &gradient);
  const double h = 1e-6;
  for (int k : {0, 3, 11, 20, 38})
    for (int i = 0; i < 3; ++i) {
      Eigen::Matrix3Xd plus = centres, minus = centres;
      plus(i, k) += h;
      minus(i, k) -= h;
      DeformedField fp = field, fm = field;
      fp.setCentres(plus);
      fm.setCentres(minus);
      const double fd = (objective.evaluate(fp, s.points, anchors, nullptr) - objective.evaluate(fm, s.points, anchors, nullptr)) / (2 * h);
      const double expected = s.free_mask[static_cast<size_t>(k)] ? fd : 0.0;
      EXPECT_NEAR(gradient(i, k), expected, 1e-6 * (1.0 + std::abs(fd))) << "kernel " << k << " axis " << i;
    }
}

}  // namespace
}  // namespace rbfmuscle
