// SPDX-License-Identifier: Apache-2.0
/// GaussianField: closed form of one Gaussian, every derivative against
/// central finite differences (at random points, exactly at centres and
/// 1e-6 mm from them), κ = tr(H)/3, translation invariance, cut-off
/// semantics, grid vs brute force bitwise, and bad input.
#include "rbf/gaussian_field.h"

#include "rbf_test_fields.h"
#include "support/eigen_compare.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace rbfmuscle {
namespace {

using test::centralDifference;
using test::isApprox;
using test::makeRandomField;

constexpr double kRelTol = 1e-6;
constexpr double kEps = std::numeric_limits<double>::epsilon();

/// Random points, points exactly at centres, and points 1e-6 mm from centres.
std::vector<Eigen::Vector3d> makeProbePoints(const GaussianField& field, std::mt19937& rng) {
  std::uniform_real_distribution<double> box(-6.0, 6.0);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 4; ++i) points.emplace_back(box(rng), box(rng), box(rng));
  for (int k = 0; k < 4; ++k) {
    points.push_back(field.getCentres().col(k));
    points.push_back(field.getCentres().col(k) +
                     1e-6 * Eigen::Vector3d(box(rng), box(rng), box(rng)).normalized());
  }
  return points;
}

/// Σ |λᵢ| αᵢ^power: the natural magnitude of a quantity of that order.
double scaleOf(const GaussianField& field, double power) {
  return (field.getWeights().cwiseAbs().array() * field.getShapes().array().pow(power)).sum();
}

class GaussianFieldDerivatives : public ::testing::Test {
 protected:
  std::mt19937 rng_{7};
  // No cut-off: a cut-off discontinuity would spoil the finite differences.
  GaussianField field_ = makeRandomField(rng_, 30, 1e-3, 1.0, 6.0, 0.0);
  // FD step relative to the narrowest Gaussian's width 1/√α_max.
  double h_ = 1e-4 / std::sqrt(field_.getShapes().maxCoeff());
};

TEST(GaussianField, SingleGaussianMatchesClosedForm) {
  const double alpha = 0.3, lambda = 2.0, b = -1.0;
  const Eigen::Vector3d xi(1.0, 2.0, 3.0);
  GaussianField field(b, 0.0);
  EXPECT_EQ(field.addCentre(xi, lambda, alpha), 0);
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(1.5, 1.0, 3.7), xi, Eigen::Vector3d(4, 4, 4)}) {
    const Eigen::Vector3d d = p - xi;
    const double r2 = d.squaredNorm();
    const double phi = std::exp(-alpha * r2);
    const FieldEvaluation e = field.calcEvaluation(p);
    EXPECT_NEAR(e.value, b + lambda * phi, 1e-15);
    EXPECT_TRUE(isApprox(e.gradient, Eigen::Vector3d(-2 * alpha * lambda * phi * d), 1e-14, 1e-15));
    const Eigen::Matrix3d hessian =
        2 * alpha * lambda * phi * (2 * alpha * d * d.transpose() - Eigen::Matrix3d::Identity());
    EXPECT_TRUE(isApprox(e.hessian, hessian, 1e-14, 1e-15));
    EXPECT_NEAR(field.calcMeanCurvature(p),
                (2.0 / 3.0) * alpha * lambda * phi * (2 * alpha * r2 - 3), 1e-14);
  }
  // At the centre κ = −2αλ (a Gaussian bump is a concave cap there).
  EXPECT_NEAR(field.calcMeanCurvature(xi), -2 * alpha * lambda, 1e-15);
  EXPECT_EQ(field.getCutoffRadius(0), std::numeric_limits<double>::infinity());
}

TEST_F(GaussianFieldDerivatives, GradientAndHessianMatchFiniteDifferences) {
  const auto value = [&](const Eigen::Vector3d& x) {
    return Eigen::VectorXd::Constant(1, field_.calcValue(x));
  };
  const auto gradient = [&](const Eigen::Vector3d& x) {
    return Eigen::VectorXd(field_.calcGradient(x));
  };
  for (const Eigen::Vector3d& p : makeProbePoints(field_, rng_)) {
    SCOPED_TRACE(::testing::Message() << "p = " << p.transpose());
    const FieldEvaluation e = field_.calcEvaluation(p);
    EXPECT_EQ(e.value, field_.calcValue(p));
    EXPECT_TRUE(isApprox(e.gradient, field_.calcGradient(p), 1e-14));
    const Eigen::MatrixXd fd_gradient = centralDifference(value, p, h_).transpose();
    EXPECT_TRUE(isApprox(Eigen::MatrixXd(e.gradient), fd_gradient, kRelTol,
                         1e-9 * scaleOf(field_, 0.5) + 10 * kEps * scaleOf(field_, 0) / h_));
    const Eigen::MatrixXd fd_hessian = centralDifference(gradient, p, h_);
    EXPECT_TRUE(isApprox(Eigen::MatrixXd(e.hessian), fd_hessian, kRelTol,
                         1e-9 * scaleOf(field_, 1) + 10 * kEps * scaleOf(field_, 0.5) / h_));
    EXPECT_TRUE(isApprox(e.hessian, e.hessian.transpose(), 0.0, 0.0));
  }
}

TEST_F(GaussianFieldDerivatives, MeanCurvatureIsTraceOverThreeAndItsGradientMatchesFD) {
  const auto kappa = [&](const Eigen::Vector3d& x) {
    return Eigen::VectorXd::Constant(1, field_.calcMeanCurvature(x));
  };
  for (const Eigen::Vector3d& p : makeProbePoints(field_, rng_)) {
    SCOPED_TRACE(::testing::Message() << "p = " << p.transpose());
    const double trace = field_.calcEvaluation(p).hessian.trace() / 3.0;
    EXPECT_NEAR(field_.calcMeanCurvature(p), trace, 1e-13 * scaleOf(field_, 1));
    const Eigen::MatrixXd fd = centralDifference(kappa, p, h_).transpose();
    EXPECT_TRUE(isApprox(Eigen::MatrixXd(field_.calcMeanCurvatureGradient(p)), fd, kRelTol,
                         1e-9 * scaleOf(field_, 1.5) + 10 * kEps * scaleOf(field_, 1) / h_));
  }
}

TEST_F(GaussianFieldDerivatives, DerivativesWrtCentresAndWeightsMatchFD) {
  for (const Eigen::Vector3d& p : makeProbePoints(field_, rng_)) {
    for (int k = 0; k < field_.getNumCentres(); ++k) {
      SCOPED_TRACE(::testing::Message() << "p = " << p.transpose() << ", centre " << k);
      const double alpha = field_.getShapes()[k];
      const double lambda = std::abs(field_.getWeights()[k]);
      const double h = 1e-4 / std::sqrt(alpha);
      const auto moved = [&](const Eigen::Vector3d& xi) {
        GaussianField f = field_;
        Eigen::Matrix3Xd centres = f.getCentres();
        centres.col(k) = xi;
        f.setCentrePositions(centres);
        Eigen::VectorXd out(2);
        out << f.calcValue(p), f.calcMeanCurvature(p);
        return out;
      };
      const Eigen::MatrixXd fd = centralDifference(moved, field_.getCentres().col(k), h);
      EXPECT_TRUE(isApprox(Eigen::MatrixXd(field_.calcValueDerivativeWrtCentre(p, k).transpose()),
                           fd.row(0), kRelTol,
                           1e-9 * lambda * std::sqrt(alpha) + 10 * kEps * scaleOf(field_, 0) / h));
      EXPECT_TRUE(isApprox(
          Eigen::MatrixXd(field_.calcMeanCurvatureDerivativeWrtCentre(p, k).transpose()), fd.row(1),
          kRelTol, 1e-9 * lambda * std::pow(alpha, 1.5) + 10 * kEps * scaleOf(field_, 1) / h));
      // κ is linear in λₖ: a central difference with a unit step is exact up to rounding.
      GaussianField plus = field_, minus = field_;
      Eigen::VectorXd w = field_.getWeights();
      w[k] += 0.5;
      plus.setWeights(w);
      w[k] -= 1.0;
      minus.setWeights(w);
      const double fd_weight = plus.calcMeanCurvature(p) - minus.calcMeanCurvature(p);
      EXPECT_NEAR(field_.calcMeanCurvatureDerivativeWrtWeight(p, k), fd_weight,
                  kRelTol * std::abs(fd_weight) + 10 * kEps * scaleOf(field_, 1));
    }
  }
}

TEST_F(GaussianFieldDerivatives, DerivativesAreInvariantUnderTranslation) {
  // Moving x and every ξ together leaves f unchanged: ∇ₓ = −Σₖ ∂/∂ξₖ.
  for (const Eigen::Vector3d& p : makeProbePoints(field_, rng_)) {
    Eigen::Vector3d sum_f = Eigen::Vector3d::Zero(), sum_kappa = Eigen::Vector3d::Zero();
    for (int k = 0; k < field_.getNumCentres(); ++k) {
      sum_f += field_.calcValueDerivativeWrtCentre(p, k);
      sum_kappa += field_.calcMeanCurvatureDerivativeWrtCentre(p, k);
    }
    EXPECT_TRUE(isApprox(field_.calcGradient(p), -sum_f, 1e-14, 1e-15 * scaleOf(field_, 0.5)));
    EXPECT_TRUE(isApprox(field_.calcMeanCurvatureGradient(p), -sum_kappa, 1e-14,
                         1e-15 * scaleOf(field_, 1.5)));
  }
}

TEST(GaussianField, CutoffDropsCentresWherePhiBelowEpsilon) {
  const double alpha = 0.05, lambda = 3.0, epsilon = 1e-6;
  GaussianField field(0.0, epsilon);
  field.addCentre(Eigen::Vector3d::Zero(), lambda, alpha);
  const double radius = std::sqrt(std::log(1.0 / epsilon) / alpha);
  EXPECT_DOUBLE_EQ(field.getCutoffRadius(0), radius);
  const Eigen::Vector3d dir = Eigen::Vector3d(1, 2, -2).normalized();
  EXPECT_NEAR(field.calcValue((1 - 1e-9) * radius * dir), lambda * epsilon, 1e-12);
  EXPECT_EQ(field.calcValue((1 + 1e-9) * radius * dir), 0.0);
  ActiveCentres active;
  field.findActiveCentres((1 + 1e-9) * radius * dir, active);
  EXPECT_EQ(active.size(), 0);
  field.findActiveCentres(0.5 * radius * dir, active);
  ASSERT_EQ(active.size(), 1);
  EXPECT_DOUBLE_EQ(active.phi[0], std::exp(-alpha * 0.25 * radius * radius));
  EXPECT_DOUBLE_EQ(active.r2_mm2[0], 0.25 * radius * radius);
}

/// Every query of `a` and `b` gives bitwise the same numbers at `points`.
void expectBitwiseEqual(const GaussianField& a, const GaussianField& b,
                        const Eigen::Matrix3Xd& points) {
  ActiveCentres active_a, active_b;
  for (int i = 0; i < points.cols(); ++i) {
    const Eigen::Vector3d p = points.col(i);
    a.findActiveCentres(p, active_a);
    b.findActiveCentres(p, active_b);
    ASSERT_EQ(active_a.indices, active_b.indices) << "point " << i;
    ASSERT_EQ(active_a.phi, active_b.phi);
    const FieldEvaluation ea = a.calcEvaluation(p), eb = b.calcEvaluation(p);
    ASSERT_EQ(ea.value, eb.value);
    ASSERT_TRUE(ea.gradient == eb.gradient);
    ASSERT_TRUE(ea.hessian == eb.hessian);
    ASSERT_EQ(a.calcMeanCurvature(p), b.calcMeanCurvature(p));
    ASSERT_TRUE(a.calcMeanCurvatureGradient(p) == b.calcMeanCurvatureGradient(p));
  }
  Eigen::VectorXd va, vb, ka, kb;
  a.calcValues(points, va);
  b.calcValues(points, vb);
  a.calcMeanCurvatures(points, ka);
  b.calcMeanCurvatures(points, kb);
  ASSERT_TRUE(va == vb);
  ASSERT_TRUE(ka == kb);
  for (int i = 0; i < points.cols(); ++i) {
    ASSERT_EQ(va[i], a.calcValue(points.col(i)));
    ASSERT_EQ(ka[i], a.calcMeanCurvature(points.col(i)));
  }
}

TEST(GaussianField, GridAndBruteForceAgreeBitwise) {
  std::mt19937 rng(11);
  // Shapes over five orders of magnitude, default cut-off.
  GaussianField grid = makeRandomField(rng, 400, 1e-4, 10.0, 40.0, GaussianField::kDefaultCutoff);
  std::uniform_real_distribution<double> box(-60.0, 60.0);
  Eigen::Matrix3Xd points(3, 600);
  for (int i = 0; i < points.cols(); ++i)
    points.col(i) = i < 100 ? Eigen::Vector3d(grid.getCentres().col(i))
                            : Eigen::Vector3d(box(rng), box(rng), box(rng));
  GaussianField brute = grid;
  brute.setUseGrid(false);
  ASSERT_TRUE(grid.getUseGrid());
  expectBitwiseEqual(grid, brute, points);

  // After the centres move (cheap grid update) and after one is added.
  std::normal_distribution<double> step(0.0, 3.0);
  Eigen::Matrix3Xd centres = grid.getCentres();
  for (int k = 0; k < centres.cols(); ++k)
    for (int a = 0; a < 3; ++a) centres(a, k) += step(rng);
  grid.setCentrePositions(centres);
  brute.setCentrePositions(centres);
  expectBitwiseEqual(grid, brute, points);
  grid.addCentre(Eigen::Vector3d(1, 2, 3), 0.7, 2.5);
  brute.addCentre(Eigen::Vector3d(1, 2, 3), 0.7, 2.5);
  expectBitwiseEqual(grid, brute, points);

  // The active set is exactly {k : αₖ rₖ² ≤ ln(1/ε)}, i.e. φₖ ≥ ε.
  ActiveCentres active;
  for (int i = 0; i < points.cols(); ++i) {
    grid.findActiveCentres(points.col(i), active);
    std::vector<int> expected;
    for (int k = 0; k < grid.getNumCentres(); ++k)
      if (std::exp(-grid.getShapes()[k] * (points.col(i) - grid.getCentres().col(k)).squaredNorm()) >=
          grid.getCutoff())
        expected.push_back(k);
    ASSERT_EQ(active.indices, expected) << "point " << i;
  }
}

TEST(GaussianField, RejectsBadInputNamingTheValue) {
  GaussianField field;
  const auto expectMessage = [](const auto& call, const std::string& text) {
    try {
      call();
      ADD_FAILURE() << "expected an exception mentioning '" << text << "'";
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
  };
  expectMessage([&] { field.addCentre(Eigen::Vector3d::Zero(), 1.0, -2.0); },
                "centre 0 shape -2");
  expectMessage([&] { field.setCentres(Eigen::Matrix3Xd::Zero(3, 2), Eigen::VectorXd::Ones(3),
                                       Eigen::VectorXd::Ones(2)); },
                "2 centres, 3 weights");
  expectMessage([&] { field.setCutoff(1.0); }, "cut-off epsilon 1");
  field.addCentre(Eigen::Vector3d::Zero(), 1.0, 1.0);
  expectMessage([&] { field.setCentrePositions(Eigen::Matrix3Xd::Zero(3, 2)); },
                "2 centres, expected 1");
  expectMessage([&] { field.calcMeanCurvatureDerivativeWrtCentre(Eigen::Vector3d::Zero(), 1); },
                "centre index 1");
  expectMessage([&] { field.calcValue(Eigen::Vector3d(NAN, 0, 0)); }, "query point");
}

}  // namespace
}  // namespace rbfmuscle
