#include "dynamics/muscle_deformer.h"

#include "dynamics_test_shapes.h"
#include "geometry/iso_surface.h"
#include "geometry/mesh_measures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace rbfmuscle {
namespace {

const Eigen::Vector3d kKnee(0.0, 0.0, 0.0);

/// Bone 0 at rest, bone 1 turned about z through the rod's middle.
std::vector<Eigen::Isometry3d> bend(double angle_rad) {
  return {Eigen::Isometry3d::Identity(), test::makeRotationAbout(kKnee, Eigen::Vector3d::UnitZ(), angle_rad)};
}

TEST(MuscleDeformer, RestPoseIsTheRestField) {
  const GaussianField field = test::makeRodField();
  MuscleDeformer d(field, test::makeRodAttachments(field));
  const DeformResult& r = d.update(bend(0.0));
  EXPECT_EQ(d.getField().getCentres(), field.getCentres());
  EXPECT_EQ(r.iterations, 0);
  EXPECT_NEAR(r.volume_ratio, 1.0, 1e-12);
}

// extractSurface reads the field from a separable grid evaluation: the same mesh as the
// extraction evaluating every node itself, up to rounding of the node values.
TEST(MuscleDeformer, ExtractedSurfaceEqualsTheNodeByNodeExtraction) {
  const GaussianField field = test::makeRodField();
  MuscleDeformer d(field, test::makeRodAttachments(field));
  d.update(bend(0.4));
  const GaussianField& f = d.getField();
  const TriangleMesh fast = d.extractSurface(0.7);
  const TriangleMesh direct = extractIsoSurface([&f](const Eigen::Matrix3Xd& p, Eigen::VectorXd& v) { f.calcValues(p, v); },
                                                d.calcCurrentBox(0.7), 0.7);
  ASSERT_GT(fast.countVertices(), 100);
  ASSERT_EQ(fast.countVertices(), direct.countVertices());
  ASSERT_EQ(fast.triangles, direct.triangles);
  EXPECT_LT((fast.vertices_mm - direct.vertices_mm).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(MuscleDeformer, CommonRigidMotionMovesTheSurfaceRigidly) {
  const GaussianField field = test::makeRodField();
  MuscleDeformer d(field, test::makeRodAttachments(field));
  const TriangleMesh rest = d.extractSurface(0.7);
  Eigen::Isometry3d x = test::makeRotationAbout(Eigen::Vector3d(5, -3, 2), Eigen::Vector3d(1, 1, 0.3), 0.6);
  x.translation() += Eigen::Vector3d(20, -10, 5);
  const DeformResult& r = d.update({x, x});
  TriangleMesh moved = rest;
  moved.vertices_mm = x * rest.vertices_mm;
  EXPECT_LE(test::calcMeanSurfaceDistance(moved, d.extractSurface(0.7)), 0.5);
  EXPECT_NEAR(r.volume_ratio, 1.0, 1e-3);
}

TEST(MuscleDeformer, BendingKeepsTheVolumeAndTheAttachments) {
  const GaussianField field = test::makeRodField();
  const Attachments att = test::makeRodAttachments(field);
  MuscleDeformer d(field, att);
  const double rest_volume = calcVolume(d.extractSurface(0.5));
  const std::vector<Eigen::Isometry3d> motion = bend(40.0 * M_PI / 180.0);
  const DeformResult& r = d.update(motion);
  EXPECT_NEAR(r.volume_ratio, 1.0, 1e-3) << toString(r.volume_stop);
  EXPECT_LE(r.descent_cost_final, r.descent_cost_initial);
  // The mesh's own volume (independent of the quadrature) within 3 %.
  const TriangleMesh bent = d.extractSurface(0.5);
  EXPECT_NEAR(calcVolume(bent) / rest_volume, 1.0, 0.03);
  EXPECT_EQ(countComponents(bent), 1);
  for (int k = 0; k < field.getNumCentres(); ++k) {
    const int b = att.bone_of_centre[static_cast<size_t>(k)];
    if (b < 0) continue;
    const Eigen::Vector3d expected = motion[static_cast<size_t>(b)] * Eigen::Vector3d(field.getCentres().col(k));
    EXPECT_LT((d.getField().getCentres().col(k) - expected).norm(), 1e-9) << "centre " << k;
  }
}

/// Mean move along +y, from `rest`, of the free centres whose rest x is in [−5, 5] mm.
double meanPushOfMiddle(const Eigen::Matrix3Xd& centres, const GaussianField& rest, const Attachments& att) {
  double sum = 0.0;
  int n = 0;
  for (int k = 0; k < rest.getNumCentres(); ++k)
    if (!att.isAttached(k) && std::abs(rest.getCentres()(0, k)) <= 5.0) {
      sum += centres(1, k) - rest.getCentres()(1, k);
      ++n;
    }
  return n > 0 ? sum / n : NAN;
}

// The contact response hands its push back as a kept correction: the next frame's
// descent anchors and quadrature points move with it, so the push is not undone. With
// setCurrentCentres (a disturbance, as in the restore test) the next frame pulls back.
TEST(MuscleDeformer, AKeptCorrectionStaysInTheNextFramesAndADisturbanceIsPulledBack) {
  const GaussianField field = test::makeRodField();
  const Attachments att = test::makeRodAttachments(field);
  Eigen::Matrix3Xd pushed = field.getCentres();
  for (int k = 0; k < field.getNumCentres(); ++k)
    if (!att.isAttached(k) && std::abs(pushed(0, k)) <= 5.0) pushed(1, k) += 1.0;
  ASSERT_NEAR(meanPushOfMiddle(pushed, field, att), 1.0, 1e-12);
  double kept = 0.0, disturbed = 0.0;
  for (const bool keep : {true, false}) {
    MuscleDeformer d(field, att);
    d.update(bend(0.0));
    if (keep) {
      d.applyKeptCorrection(pushed);
    } else {
      d.setCurrentCentres(pushed);
    }
    for (int frame = 0; frame < 3; ++frame) {
      const DeformResult& r = d.update(bend(0.0));
      EXPECT_NEAR(r.volume_ratio, 1.0, 1e-2) << "keep " << keep << " frame " << frame;
    }
    (keep ? kept : disturbed) = meanPushOfMiddle(d.getField().getCentres(), field, att);
    for (int k = 0; k < field.getNumCentres(); ++k) {
      if (att.isAttached(k)) {
        EXPECT_EQ(d.getField().getCentres().col(k), field.getCentres().col(k)) << k;
      }
    }
  }
  std::printf("push of 1 mm after 3 frames: kept %.3f mm, disturbance %.3f mm\n", kept, disturbed);
  EXPECT_GT(kept, 0.9);
  EXPECT_LT(disturbed, kept - 0.2);
}

// Regression: the Jacobian of the prediction used the rest weights of the unshifted
// point, so it was the Jacobian of a rigid motion (1 everywhere) and the volume of the
// carried points ignored the stretch of the blend. Checked against det ∂P/∂x of the
// blend map P(x) = DQB(w(x)) x by central differences with the deformer's step h/2
// (the soft-min weights have kinks where the nearest attached centre changes, so a
// finer step would differ there by more than the truncation error).
TEST(MuscleDeformer, JacobianIsTheDeterminantOfTheBlendMap) {
  const GaussianField field = test::makeRodField();
  const Attachments att = test::makeRodAttachments(field);
  DeformerSettings settings;
  MuscleDeformer d(field, att, settings);
  const std::vector<Eigen::Isometry3d> motion = bend(60.0 * M_PI / 180.0);
  d.update(motion);
  std::vector<DualQuaternion> dq;
  for (const Eigen::Isometry3d& x : motion) dq.push_back(toDualQuaternion(x));
  const Eigen::Matrix3Xd& rest = d.getQuadrature().points_mm;
  const double h = 0.5 * d.getQuadrature().cell_mm;
  double largest_change = 0.0;
  for (Eigen::Index j = 0; j < rest.cols(); j += 37) {
    Eigen::Matrix3d jac;
    for (int i = 0; i < 3; ++i) {
      Eigen::Matrix3Xd p(3, 2);
      p.col(0) = rest.col(j) + h * Eigen::Vector3d::Unit(i);
      p.col(1) = rest.col(j) - h * Eigen::Vector3d::Unit(i);
      Eigen::Matrix3Xd moved;
      predictPoints(p, calcBlendWeights(p, field.getCentres(), att, settings.blend_length_mm), dq, moved);
      jac.col(i) = (moved.col(0) - moved.col(1)) / (2.0 * h);
    }
    EXPECT_NEAR(d.getJacobians()(j), jac.determinant(), 1e-9) << "point " << j;
    largest_change = std::max(largest_change, std::abs(jac.determinant() - 1.0));
  }
  EXPECT_GT(largest_change, 0.01);  // the bend does stretch the blend zone
}

TEST(MuscleDeformer, TwoRunsAreBitwiseEqual) {
  const GaussianField field = test::makeRodField();
  const Attachments att = test::makeRodAttachments(field);
  MuscleDeformer a(field, att), b(field, att);
  for (int frame = 1; frame <= 4; ++frame) {
    const double angle = 0.15 * frame;
    const DeformResult ra = a.update(bend(angle));
    const DeformResult rb = b.update(bend(angle));
    ASSERT_EQ(a.getField().getCentres(), b.getField().getCentres()) << "frame " << frame;
    ASSERT_EQ(a.getField().getOffset(), b.getField().getOffset());
    ASSERT_EQ(ra.curvature_cost, rb.curvature_cost);
    ASSERT_EQ(ra.volume_mm3, rb.volume_mm3);
    ASSERT_EQ(ra.iterations, rb.iterations);
  }
}

// Regression guard: very narrow (10 mm⁻²) and very wide (1e-4 mm⁻²) Gaussians and
// 10° steps must give finite numbers and a report, not NaN or a crash.
TEST(MuscleDeformer, ExtremeShapesAndLargeStepsStayFinite) {
  GaussianField rod = test::makeRodField();
  Eigen::Matrix3Xd xi = rod.getCentres();
  Eigen::VectorXd lambda = rod.getWeights(), alpha = rod.getShapes();
  alpha(15) = 10.0;
  lambda(15) = 3.0;
  alpha(20) = 1e-4;
  lambda(20) = 0.5;
  const GaussianField field(-5.0, xi, lambda, alpha);
  MuscleDeformer d(field, test::makeRodAttachments(field));
  for (int frame = 1; frame <= 6; ++frame) {
    const DeformResult& r = d.update(bend(frame * 10.0 * M_PI / 180.0));
    ASSERT_TRUE(std::isfinite(r.volume_mm3) && std::isfinite(r.curvature_cost)) << "frame " << frame;
    ASSERT_TRUE(d.getField().getCentres().allFinite());
    EXPECT_LE(r.descent_cost_final, r.descent_cost_initial);
    EXPECT_FALSE(toString(r.stop_reason).empty());
  }
}

TEST(MuscleDeformer, WrongBoneCountNamesTheExpectedCount) {
  const GaussianField field = test::makeRodField();
  MuscleDeformer d(field, test::makeRodAttachments(field));
  try {
    d.update({Eigen::Isometry3d::Identity()});
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("expected 2"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rbfmuscle
