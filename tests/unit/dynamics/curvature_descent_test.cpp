#include "dynamics/curvature_descent.h"
#include "dynamics/quadrature.h"

#include "dynamics_test_shapes.h"
#include "geometry/iso_surface.h"

#include <gtest/gtest.h>

namespace rbfmuscle {
namespace {

std::vector<bool> freeMask(const Attachments& a) {
  std::vector<bool> mask(a.bone_of_centre.size());
  for (size_t k = 0; k < mask.size(); ++k) mask[k] = a.bone_of_centre[k] < 0;
  return mask;
}

struct RodSetup {
  GaussianField field = test::makeRodField();
  Attachments attachments = test::makeRodAttachments(field);
  Quadrature quadrature = makeQuadrature(field, QuadratureSettings{});
  CurvatureCost cost{quadrature.points_mm, quadrature.weights_mm3, quadrature.target_curvatures};
};

TEST(CurvatureDescent, GradientMatchesFiniteDifferencesOfTheFullObjective) {
  RodSetup s;
  DescentSettings settings;
  settings.regularisation = 0.3;
  settings.regularisation_length_mm = 2.0;
  CurvatureDescent descent(s.cost, freeMask(s.attachments), settings);
  const Eigen::Matrix3Xd anchors = s.field.getCentres();
  const Eigen::Matrix3Xd start = test::perturbFreeCentres(anchors, s.attachments, 1.5, 7);
  s.field.setCentrePositions(start);
  Eigen::Matrix3Xd gradient, scratch;
  descent.calcObjective(s.field, anchors, gradient);
  const double h = 1e-5;
  for (int k = 0; k < s.field.getNumCentres(); k += 4) {
    for (int i = 0; i < 3; ++i) {
      Eigen::Matrix3Xd x = start;
      x(i, k) += h;
      s.field.setCentrePositions(x);
      const double plus = descent.calcObjective(s.field, anchors, scratch);
      x(i, k) -= 2 * h;
      s.field.setCentrePositions(x);
      const double minus = descent.calcObjective(s.field, anchors, scratch);
      const double fd = s.attachments.isAttached(k) ? 0.0 : (plus - minus) / (2 * h);
      EXPECT_NEAR(gradient(i, k), fd, 1e-6 * std::max(1.0, gradient.cwiseAbs().maxCoeff())) << "centre " << k << " axis " << i;
    }
  }
}

TEST(CurvatureDescent, NeverRaisesTheCostAndReportsIt) {
  for (unsigned seed : {1u, 2u, 3u}) {
    for (int memory : {0, 8}) {
      RodSetup s;
      DescentSettings settings;
      settings.lbfgs_memory = memory;
      settings.max_iterations = 15;
      settings.initial_step_mm = 5.0;  // deliberately too large: the line search must cope
      CurvatureDescent descent(s.cost, freeMask(s.attachments), settings);
      const Eigen::Matrix3Xd anchors = s.field.getCentres();
      s.field.setCentrePositions(test::perturbFreeCentres(anchors, s.attachments, 3.0, seed));
      const DescentReport r = descent.run(s.field, anchors);
      EXPECT_LE(r.cost_final, r.cost_initial);
      EXPECT_LT(r.cost_final, 0.5 * r.cost_initial) << "seed " << seed << " memory " << memory;
      Eigen::Matrix3Xd g;
      EXPECT_DOUBLE_EQ(descent.calcObjective(s.field, anchors, g), r.cost_final);
      EXPECT_GE(r.iterations, 1);
      EXPECT_LE(r.iterations, settings.max_iterations);
      for (int k = 0; k < s.field.getNumCentres(); ++k) {
        if (s.attachments.isAttached(k)) {
          EXPECT_EQ(s.field.getCentres().col(k), anchors.col(k));
        }
      }
    }
  }
}

TEST(CurvatureDescent, StopsAtOnceWhenNothingIsFreeOrAtTheMinimum) {
  RodSetup s;
  Attachments all = s.attachments;
  for (int& b : all.bone_of_centre) b = 0;
  CurvatureDescent none(s.cost, freeMask(all), DescentSettings{});
  EXPECT_EQ(none.run(s.field, s.field.getCentres()).stop_reason, DescentStop::kNoFreeCentres);
  CurvatureDescent descent(s.cost, freeMask(s.attachments), DescentSettings{});
  const DescentReport r = descent.run(s.field, s.field.getCentres());
  EXPECT_EQ(r.cost_initial, 0.0);
  EXPECT_EQ(r.iterations, 0);
  EXPECT_EQ(toString(r.stop_reason), "gradient_tolerance");
}

// Dissertation 8.3.1 on a small shape: free centres moved randomly by 5 % of the
// box diagonal, attachments held, pure curvature descent → back within 0.5 % of it.
TEST(CurvatureDescent, RestoresRandomlyPerturbedRod) {
  RodSetup s;
  const TriangleMesh rest = extractIsoSurface(
      [&](const Eigen::Matrix3Xd& p, Eigen::VectorXd& v) { s.field.calcValues(p, v); }, s.quadrature.box_mm, 0.7);
  const double diagonal = rest.calcBoundingBox().diagonal().norm();
  DescentSettings settings;
  settings.regularisation = 0.0;
  settings.max_iterations = 400;
  settings.cost_tolerance = 1e-9;
  settings.gradient_tolerance = 1e-7;
  CurvatureDescent descent(s.cost, freeMask(s.attachments), settings);
  const Eigen::Matrix3Xd anchors = s.field.getCentres();
  s.field.setCentrePositions(test::perturbFreeCentres(anchors, s.attachments, 0.05 * diagonal, 11));
  const DescentReport r = descent.run(s.field, anchors);
  const TriangleMesh restored = extractIsoSurface(
      [&](const Eigen::Matrix3Xd& p, Eigen::VectorXd& v) { s.field.calcValues(p, v); }, s.quadrature.box_mm, 0.7);
  const double distance = test::calcMeanSurfaceDistance(rest, restored);
  RecordProperty("mean_distance_mm", std::to_string(distance));
  EXPECT_LE(distance, 0.005 * diagonal) << "iterations " << r.iterations << " stop " << toString(r.stop_reason)
                                         << " cost " << r.cost_initial << " -> " << r.cost_final;
}

TEST(CurvatureDescent, CentreExactlyOnAQuadraturePointStaysFinite) {
  RodSetup s;
  int free_k = -1;
  for (int k = 0; k < s.field.getNumCentres() && free_k < 0; ++k)
    if (!s.attachments.isAttached(k)) free_k = k;
  Eigen::Matrix3Xd start = s.field.getCentres();
  const Eigen::Matrix3Xd anchors = start;
  start.col(free_k) = s.quadrature.points_mm.col(s.quadrature.points_mm.cols() / 2);
  s.field.setCentrePositions(start);
  CurvatureDescent descent(s.cost, freeMask(s.attachments), DescentSettings{});
  const DescentReport r = descent.run(s.field, anchors);
  EXPECT_TRUE(std::isfinite(r.cost_final));
  EXPECT_LE(r.cost_final, r.cost_initial);
  EXPECT_TRUE(s.field.getCentres().allFinite());
}

}  // namespace
}  // namespace rbfmuscle
