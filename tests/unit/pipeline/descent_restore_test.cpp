// SPDX-License-Identifier: Apache-2.0
// The curvature descent restores a shape (dissertation 8.3.1 on a small shape): the rod's free
// kernels moved at random by 5 % of its box diagonal, its attached kernels held, a pure
// curvature descent brings the surface back within 0.5 % of the diagonal.
#include "pipeline/descent_stage.h"

#include "../dynamics/dynamics_test_shapes.h"
#include "dynamics/quadrature.h"
#include "geometry/iso_surface.h"
#include "geometry/mesh_measures.h"

#include <gtest/gtest.h>

namespace rbfmuscle {
namespace {

TriangleMesh extractSurface(const DeformedField& field, const Eigen::AlignedBox3d& box) {
  return extractIsoSurface(
      [&](const Eigen::Matrix3Xd& p, Eigen::VectorXd& v) {
        v.resize(p.cols());
        for (Eigen::Index j = 0; j < p.cols(); ++j) v[j] = field.calcValue(p.col(j));
      },
      box, 0.7);
}

TEST(DescentStage, RestoresARandomlyPerturbedRod) {
  const GaussianField fit = test::makeRodField();
  const Attachments attachments = test::makeRodAttachments(fit);
  QuadratureSettings quadrature_settings;
  quadrature_settings.target_count = 2000;
  const Quadrature quadrature = makeQuadrature(fit, quadrature_settings);
  std::vector<bool> free_mask(static_cast<size_t>(fit.getNumCentres()));
  for (int k = 0; k < fit.getNumCentres(); ++k) free_mask[static_cast<size_t>(k)] = !attachments.isAttached(k);

  DescentSettings settings;
  settings.regularisation = 0.0;  // curvature alone: nothing pulls towards the perturbed place
  settings.max_iterations = 400;
  settings.cost_tolerance = 1e-12;
  settings.points = static_cast<int>(quadrature.points_mm.cols());
  MuscleState state(fit, 1e-3);
  DescentStage descent(state.field, quadrature.points_mm, quadrature.weights_mm3, free_mask, settings);

  const TriangleMesh rest = extractSurface(state.field, quadrature.box_mm);
  const double diagonal = rest.calcBoundingBox().diagonal().norm();
  for (unsigned seed : {11u, 12u, 13u}) {
    MuscleState perturbed(fit, 1e-3);
    perturbed.quadrature_mm = quadrature.points_mm;
    perturbed.anchors_mm = test::perturbFreeCentres(fit.getCentres(), attachments, 0.05 * diagonal, seed);
    perturbed.field.setCentres(perturbed.anchors_mm);
    const double moved = test::calcMeanSurfaceDistance(rest, extractSurface(perturbed.field, quadrature.box_mm));
    descent.run(perturbed, FrameInput{});
    std::vector<double> report;
    descent.appendReport(report);
    const double restored = test::calcMeanSurfaceDistance(rest, extractSurface(perturbed.field, quadrature.box_mm));
    EXPECT_LE(restored, 0.005 * diagonal) << "seed " << seed << ": mean distance " << moved << " mm perturbed, "
                                          << restored << " mm after " << report[1] << " steps (stop " << report[2] << ")";
    EXPECT_LT(restored, 0.5 * moved) << "seed " << seed;
    RecordProperty("seed_" + std::to_string(seed), std::to_string(moved) + " mm -> " + std::to_string(restored) + " mm of diagonal " + std::to_string(diagonal));
    for (int k = 0; k < fit.getNumCentres(); ++k)
      if (attachments.isAttached(k)) {
        EXPECT_EQ(perturbed.field.getCentres().col(k), fit.getCentres().col(k));
      }
  }
}

}  // namespace
}  // namespace rbfmuscle
