/// CurvatureCost: zero at its own targets, equal to the direct quadrature
/// sum, gradient against central finite differences, a descent step lowers
/// it, invariant under rigid motion, bitwise deterministic over thread
/// counts and grid/brute-force paths, and bad input rejected.
#include "rbf/curvature_cost.h"

#include "rbf_test_fields.h"
#include "support/eigen_compare.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace rbfmuscle {
namespace {

using test::isApprox;
using test::makeRandomField;

Eigen::Matrix3Xd makeQuadraturePoints(std::mt19937& rng, int m, double half_side_mm) {
  std::uniform_real_distribution<double> box(-half_side_mm, half_side_mm);
  Eigen::Matrix3Xd points(3, m);
  for (int q = 0; q < m; ++q) points.col(q) = Eigen::Vector3d(box(rng), box(rng), box(rng));
  return points;
}

Eigen::VectorXd makeWeights(std::mt19937& rng, int m) {
  std::uniform_real_distribution<double> w(0.1, 2.0);
  Eigen::VectorXd weights(m);
  for (int q = 0; q < m; ++q) weights[q] = w(rng);
  return weights;
}

/// The field with every centre moved by a random offset of about `sigma_mm`.
GaussianField perturbed(const GaussianField& field, std::mt19937& rng, double sigma_mm) {
  std::normal_distribution<double> step(0.0, sigma_mm);
  Eigen::Matrix3Xd centres = field.getCentres();
  for (int k = 0; k < centres.cols(); ++k)
    for (int a = 0; a < 3; ++a) centres(a, k) += step(rng);
  GaussianField moved = field;
  moved.setCentrePositions(centres);
  return moved;
}

TEST(CurvatureCost, ZeroCostAndGradientAtTheFieldsOwnCurvature) {
  std::mt19937 rng(3);
  const GaussianField field =
      makeRandomField(rng, 200, 1e-3, 1.0, 20.0, GaussianField::kDefaultCutoff);
  const Eigen::Matrix3Xd points = makeQuadraturePoints(rng, 3000, 25.0);
  const CurvatureCost cost = CurvatureCost::fromField(field, points, makeWeights(rng, 3000));
  Eigen::Matrix3Xd grad;
  EXPECT_EQ(cost.calcCostAndGradient(field, grad), 0.0);
  EXPECT_EQ(grad.cols(), 200);
  EXPECT_TRUE(grad.isZero(0.0));
  EXPECT_EQ(cost.calcCost(field), 0.0);
  // And positive once the centres move.
  EXPECT_GT(cost.calcCost(perturbed(field, rng, 0.5)), 0.0);
}

TEST(CurvatureCost, EqualsTheDirectQuadratureSum) {
  std::mt19937 rng(4);
  const GaussianField field =
      makeRandomField(rng, 100, 1e-3, 1.0, 15.0, GaussianField::kDefaultCutoff);
  const Eigen::Matrix3Xd points = makeQuadraturePoints(rng, 1000, 18.0);
  const Eigen::VectorXd weights = makeWeights(rng, 1000);
  const Eigen::VectorXd targets = CurvatureCost::calcTargetCurvatures(perturbed(field, rng, 1.0), points);
  const CurvatureCost cost(points, weights, targets);
  double expected = 0.0;
  for (int q = 0; q < points.cols(); ++q)
    expected += weights[q] * std::pow(field.calcMeanCurvature(points.col(q)) - targets[q], 2);
  EXPECT_NEAR(cost.calcCost(field), expected, 1e-12 * expected);
}

TEST(CurvatureCost, GradientMatchesFiniteDifferences) {
  std::mt19937 rng(5);
  // No cut-off, so C is smooth in the centres.
  const GaussianField field = makeRandomField(rng, 15, 1e-3, 1.0, 6.0, 0.0);
  const Eigen::Matrix3Xd points = makeQuadraturePoints(rng, 400, 8.0);
  const CurvatureCost cost(points, makeWeights(rng, 400),
                           CurvatureCost::calcTargetCurvatures(perturbed(field, rng, 1.0), points));
  Eigen::Matrix3Xd grad;
  const double c0 = cost.calcCostAndGradient(field, grad);
  ASSERT_GT(c0, 0.0);
  for (int k = 0; k < field.getNumCentres(); ++k) {
    const double h = 1e-4 / std::sqrt(field.getShapes()[k]);
    Eigen::Vector3d fd;
    for (int a = 0; a < 3; ++a) {
      Eigen::Matrix3Xd centres = field.getCentres();
      GaussianField plus = field, minus = field;
      centres(a, k) += h;
      plus.setCentrePositions(centres);
      centres(a, k) -= 2 * h;
      minus.setCentrePositions(centres);
      fd[a] = (cost.calcCost(plus) - cost.calcCost(minus)) / (2 * h);
    }
    EXPECT_TRUE(isApprox(Eigen::Vector3d(grad.col(k)), fd, 1e-6,
                         100 * std::numeric_limits<double>::epsilon() * c0 / h))
        << "centre " << k << " shape " << field.getShapes()[k];
  }
}

TEST(CurvatureCost, SmallDescentStepLowersTheCost) {
  std::mt19937 rng(6);
  GaussianField field = makeRandomField(rng, 80, 1e-2, 1.0, 12.0, GaussianField::kDefaultCutoff);
  const Eigen::Matrix3Xd points = makeQuadraturePoints(rng, 2000, 14.0);
  const CurvatureCost cost = CurvatureCost::fromField(field, points, makeWeights(rng, 2000));
  field = perturbed(field, rng, 0.3);
  Eigen::Matrix3Xd grad;
  double c = cost.calcCostAndGradient(field, grad);
  for (int step = 0; step < 5; ++step) {
    const double scale = 1e-3 / grad.cwiseAbs().maxCoeff();  // largest move 1e-3 mm
    field.setCentrePositions(field.getCentres() - scale * grad);
    const double next = cost.calcCostAndGradient(field, grad);
    EXPECT_LT(next, c) << "step " << step;
    c = next;
  }
}

TEST(CurvatureCost, InvariantUnderRigidMotion) {
  std::mt19937 rng(8);
  const GaussianField field =
      makeRandomField(rng, 60, 1e-2, 1.0, 10.0, GaussianField::kDefaultCutoff);
  const Eigen::Matrix3Xd points = makeQuadraturePoints(rng, 800, 12.0);
  const Eigen::VectorXd weights = makeWeights(rng, 800);
  const CurvatureCost cost(points, weights,
                           CurvatureCost::calcTargetCurvatures(perturbed(field, rng, 0.5), points));
  Eigen::Matrix3Xd grad;
  const double c = cost.calcCostAndGradient(field, grad);

  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized())
                                .toRotationMatrix();
  const Eigen::Vector3d t(30.0, -12.0, 5.0);
  GaussianField moved = field;
  moved.setCentrePositions((R * field.getCentres()).colwise() + t);
  CurvatureCost moved_cost = cost;
  moved_cost.setPoints((R * points).colwise() + t);
  Eigen::Matrix3Xd moved_grad;
  EXPECT_NEAR(moved_cost.calcCostAndGradient(moved, moved_grad), c, 1e-9 * c);
  EXPECT_TRUE(isApprox(moved_grad, R * grad, 1e-8));
}

TEST(CurvatureCost, BitwiseDeterministicOverRunsThreadsAndPaths) {
  std::mt19937 rng(9);
  GaussianField field = makeRandomField(rng, 300, 1e-4, 10.0, 25.0, GaussianField::kDefaultCutoff);
  const Eigen::Matrix3Xd points = makeQuadraturePoints(rng, 5000, 30.0);
  const CurvatureCost cost(points, makeWeights(rng, 5000),
                           CurvatureCost::calcTargetCurvatures(perturbed(field, rng, 1.0), points));
  Eigen::Matrix3Xd reference, grad;
  const double c = cost.calcCostAndGradient(field, reference);
  EXPECT_EQ(cost.calcCost(field), c);
  EXPECT_EQ(cost.calcCostAndGradient(field, grad), c);
  EXPECT_TRUE(grad == reference);
#ifdef _OPENMP
  const int threads = omp_get_max_threads();
  for (int n : {1, 2, 3}) {
    omp_set_num_threads(n);
    EXPECT_EQ(cost.calcCostAndGradient(field, grad), c) << n << " threads";
    EXPECT_TRUE(grad == reference) << n << " threads";
  }
  omp_set_num_threads(threads);
#endif
  field.setUseGrid(false);
  EXPECT_EQ(cost.calcCostAndGradient(field, grad), c);
  EXPECT_TRUE(grad == reference);
}

// The neighbour lists of one object, kept while centres move by less than the skin and
// rebuilt beyond it, give bitwise the numbers of a fresh object (lists built from the
// current centres) at every step: steps of 0.4 mm cross the 1 mm skin on the third.
TEST(CurvatureCost, NeighbourListsGiveAFreshObjectsNumbersWhileCentresMove) {
  std::mt19937 rng(21);
  GaussianField field = makeRandomField(rng, 300, 0.01, 1.0, 25.0, GaussianField::kDefaultCutoff);
  const Eigen::Matrix3Xd points = makeQuadraturePoints(rng, 3000, 30.0);
  const Eigen::VectorXd weights = makeWeights(rng, 3000);
  const Eigen::VectorXd targets = CurvatureCost::calcTargetCurvatures(perturbed(field, rng, 1.0), points);
  const CurvatureCost kept(points, weights, targets);
  const Eigen::Vector3d step = Eigen::Vector3d(0.4, -0.2, 0.1).normalized() * 0.4;
  for (int s = 0; s < 6; ++s) {
    Eigen::Matrix3Xd centres = field.getCentres();
    centres.colwise() += step;
    centres.col(s) -= 3.0 * step;  // one centre moving the other way
    field.setCentrePositions(centres);
    const CurvatureCost fresh(points, weights, targets);
    Eigen::Matrix3Xd grad_kept, grad_fresh;
    EXPECT_EQ(kept.calcCostAndGradient(field, grad_kept), fresh.calcCostAndGradient(field, grad_fresh)) << s;
    EXPECT_TRUE(grad_kept == grad_fresh) << s;
    EXPECT_EQ(kept.calcCost(field), fresh.calcCost(field)) << s;
  }
}

// findNearCentres lists every centre active after moves shorter than the skin (each centre
// moved 1.9 mm in a random direction, skin 2 mm): findActiveCentresAmong over the old list
// equals findActiveCentres entry by entry.
TEST(GaussianFieldNeighbours, NearListHoldsEveryCentreActiveAfterAMoveWithinTheSkin) {
  std::mt19937 rng(5);
  GaussianField field = makeRandomField(rng, 400, 0.01, 1.0, 20.0, GaussianField::kDefaultCutoff);
  const Eigen::Matrix3Xd points = makeQuadraturePoints(rng, 300, 25.0);
  std::vector<std::vector<int>> near(static_cast<size_t>(points.cols()));
  for (Eigen::Index q = 0; q < points.cols(); ++q) field.findNearCentres(points.col(q), 2.0, near[static_cast<size_t>(q)]);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::Matrix3Xd centres = field.getCentres();
  for (Eigen::Index k = 0; k < centres.cols(); ++k)
    centres.col(k) += 1.9 * Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
  field.setCentrePositions(centres);
  ActiveCentres all, among;
  size_t listed = 0, active = 0;
  for (Eigen::Index q = 0; q < points.cols(); ++q) {
    const std::vector<int>& list = near[static_cast<size_t>(q)];
    field.findActiveCentres(points.col(q), all);
    field.findActiveCentresAmong(points.col(q), list.data(), static_cast<int>(list.size()), among);
    EXPECT_EQ(among.indices, all.indices) << q;
    EXPECT_EQ(among.phi, all.phi) << q;
    EXPECT_EQ(among.r2_mm2, all.r2_mm2) << q;
    listed += list.size();
    active += all.indices.size();
  }
  EXPECT_GT(active, 0u);
  EXPECT_LT(active, listed);  // the cut-off matters here: the lists are not every centre
}

TEST(CurvatureCost, RejectsBadInputNamingTheValue) {
  const Eigen::Matrix3Xd points = Eigen::Matrix3Xd::Zero(3, 3);
  const auto expectMessage = [](const auto& call, const std::string& text) {
    try {
      call();
      ADD_FAILURE() << "expected std::invalid_argument mentioning '" << text << "'";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
  };
  expectMessage([&] { CurvatureCost(points, Eigen::Vector3d(1, -1, 1), Eigen::Vector3d::Zero()); },
                "quadrature weight 1 = -1");
  expectMessage([&] { CurvatureCost(points, Eigen::Vector2d(1, 1), Eigen::Vector3d::Zero()); },
                "3 quadrature points but 2 weights");
  expectMessage([&] { CurvatureCost(points, Eigen::Vector3d::Ones(), Eigen::Vector3d(0, NAN, 0)); },
                "target curvature 1");
  CurvatureCost cost(points, Eigen::Vector3d::Ones(), Eigen::Vector3d::Zero());
  expectMessage([&] { cost.setPoints(Eigen::Matrix3Xd::Zero(3, 4)); }, "4 points, expected 3");
}

}  // namespace
}  // namespace rbfmuscle
