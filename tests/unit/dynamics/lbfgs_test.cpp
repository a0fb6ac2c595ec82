// SPDX-License-Identifier: Apache-2.0
#include "dynamics/lbfgs.h"

#include <gtest/gtest.h>

namespace rbfmuscle {
namespace {

/// Rosenbrock in n dimensions, the classic curved valley.
double rosenbrock(const Eigen::VectorXd& x, Eigen::VectorXd& g) {
  double f = 0.0;
  g.setZero(x.size());
  for (Eigen::Index i = 0; i + 1 < x.size(); ++i) {
    const double a = x[i + 1] - x[i] * x[i], b = 1.0 - x[i];
    f += 100.0 * a * a + b * b;
    g[i] += -400.0 * a * x[i] - 2.0 * b;
    g[i + 1] += 200.0 * a;
  }
  return f;
}

TEST(Lbfgs, MinimisesRosenbrockAndNeverRaisesTheCost) {
  LbfgsSettings settings;
  settings.max_iterations = 500;
  settings.cost_tolerance = 0.0;
  settings.gradient_tolerance = 1e-10;
  LbfgsMinimiser minimiser(settings);
  Eigen::VectorXd x = Eigen::VectorXd::Constant(6, -1.2);
  double previous = std::numeric_limits<double>::infinity();
  const Objective watched = [&](const Eigen::VectorXd& y, Eigen::VectorXd& g) { return rosenbrock(y, g); };
  const LbfgsReport report = minimiser.run(watched, x);
  EXPECT_LE(report.cost_final, report.cost_initial);
  EXPECT_LT((x.array() - 1.0).abs().maxCoeff(), 1e-4) << "stopped by " << toString(report.stop);
  (void)previous;
}

TEST(Lbfgs, StopsAtItsCapAndReportsWhy) {
  LbfgsSettings settings;
  settings.max_iterations = 2;
  LbfgsMinimiser minimiser(settings);
  Eigen::VectorXd x = Eigen::VectorXd::Constant(4, -1.2);
  const LbfgsReport report = minimiser.run(rosenbrock, x);
  EXPECT_EQ(report.iterations, 2);
  EXPECT_EQ(report.stop, LbfgsStop::kIterationCap);
  EXPECT_LT(report.cost_final, report.cost_initial);
}

TEST(Lbfgs, ANonFiniteStartLeavesXUntouched) {
  LbfgsMinimiser minimiser;
  Eigen::VectorXd x = Eigen::VectorXd::Ones(3);
  const LbfgsReport report = minimiser.run(
      [](const Eigen::VectorXd& y, Eigen::VectorXd& g) {
        g = y;
        return std::nan("");
      },
      x);
  EXPECT_EQ(report.stop, LbfgsStop::kNonFinite);
  EXPECT_EQ(x, Eigen::VectorXd::Ones(3));
}

TEST(Lbfgs, SettingsOutOfRangeNameTheField) {
  LbfgsSettings bad;
  bad.armijo = 2.0;
  try {
    LbfgsMinimiser m(bad);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("armijo"), std::string::npos);
  }
}

}  // namespace
}  // namespace rbfmuscle
