#include "dynamics/surface_step_limiter.h"

#include "dynamics/field_surface.h"
#include "dynamics/muscle_deformer.h"
#include "dynamics_test_shapes.h"
#include "geometry/mesh_distance.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace rbfmuscle {
namespace {

const Eigen::AlignedBox3d kBox(Eigen::Vector3d::Constant(-20.0), Eigen::Vector3d::Constant(20.0));

/// Radius (mm) of the sphere λ e^{−α r²} − 5 = 0 of a one-centre field.
double sphereRadius(const GaussianField& f) {
  return std::sqrt(std::log(f.getWeights()(0) / 5.0) / f.getShapes()(0));
}

/// The sphere field with the radius `radius_mm`.
GaussianField sphereOfRadius(double radius_mm) {
  GaussianField f = test::makeSphereField();
  f.setWeights(Eigen::VectorXd::Constant(1, 5.0 * std::exp(f.getShapes()(0) * radius_mm * radius_mm)));
  return f;
}

/// Every one of `n` centres free, its weight unbounded.
WeightEditLimits freeLimits(int n) {
  return {std::vector<bool>(static_cast<size_t>(n), true), Eigen::VectorXd::Constant(n, 1e9)};
}

StepLimitSettings limitOf(double max_step_mm) {
  StepLimitSettings s;
  s.max_step_mm = max_step_mm;
  s.cell_mm = 0.5;
  s.max_trials = 8;
  return s;
}

// A sphere that would grow by 3 mm in one frame, its bones still, grows by the limit only: the
// radius is exact (analytic), the limit is the bisection's largest t within 0.5 mm.
TEST(SurfaceStepLimiter, AGrowthBeyondTheLimitIsTakenBackToIt) {
  SurfaceStepLimiter limiter(limitOf(0.5), freeLimits(1));
  const GaussianField start = sphereOfRadius(10.0);
  limiter.setPreviousSurface(start, kBox);
  GaussianField end = sphereOfRadius(13.0);
  const StepLimitReport r = limiter.run(start, end, kBox, {Eigen::Isometry3d::Identity()});
  EXPECT_EQ(r.stop_reason, StepLimitStop::kScaled);
  EXPECT_DOUBLE_EQ(r.full_excess_mm, 2.0);  // 2.5 mm, capped at 4 × 0.5
  EXPECT_LE(r.excess_mm, 0.0);
  EXPECT_GT(r.scale, 0.0);
  EXPECT_LT(r.scale, 1.0);
  const double grown_mm = sphereRadius(end) - 10.0;
  EXPECT_LE(grown_mm, 0.5 + 0.01);  // the meshes' chords at 0.5 mm cells
  EXPECT_GE(grown_mm, 0.5 - 3.0 / 128.0 - 0.05);  // within the bisection's resolution
}

// A surface carried 3 mm by its bone is within the limit: only the move beyond the bones' counts.
TEST(SurfaceStepLimiter, TheBonesOwnMoveIsAllowed) {
  SurfaceStepLimiter limiter(limitOf(0.5), freeLimits(1));
  const GaussianField start = sphereOfRadius(10.0);
  limiter.setPreviousSurface(start, kBox);
  const Eigen::Isometry3d step(Eigen::Translation3d(3.0, 0.0, 0.0));
  GaussianField end = start;
  end.setCentrePositions(step * start.getCentres());
  const Eigen::Matrix3Xd moved = end.getCentres();
  const StepLimitReport r = limiter.run(start, end, kBox, {Eigen::Isometry3d::Identity(), step});
  EXPECT_EQ(r.stop_reason, StepLimitStop::kWithinLimit);
  EXPECT_EQ(r.scale, 1.0);
  EXPECT_EQ(end.getCentres(), moved);
  // The same move without the bone is a jump.
  limiter.setPreviousSurface(start, kBox);
  EXPECT_NE(limiter.run(start, end, kBox, {Eigen::Isometry3d::Identity()}).stop_reason, StepLimitStop::kWithinLimit);
}

/// The 10 mm sphere with a narrow Gaussian of weight `bump` at (9, 0, 0): 15 pushes the surface
/// out to about x = 13.4 mm there; 0.01 leaves the sphere as it is.
GaussianField sphereWithBump(double bump) {
  GaussianField f = test::makeSphereField();
  f.addCentre(Eigen::Vector3d(9.0, 0.0, 0.0), bump, 0.1);
  return f;
}

// A bump of 3.4 mm that the start already has (the carried field itself jumped), so no scale can
// take it back: the pull-back lowers it locally to within the limit (here, with one centre to
// carry the edits, down to the previous surface), and the rest of the sphere
// stays where it was (its centre is attached, as a muscle's far parts are to the pull-back: other
// centres peak there). Checked on an independent finer extraction.
TEST(SurfaceStepLimiter, APointTheScalingCannotTakeBackIsPulledBackLocally) {
  WeightEditLimits bump_only = freeLimits(2);
  bump_only.free_mask[0] = false;
  SurfaceStepLimiter limiter(limitOf(0.5), bump_only);
  limiter.setPreviousSurface(sphereWithBump(0.01), kBox);
  const GaussianField start = sphereWithBump(15.0);
  GaussianField end = start;
  const StepLimitReport r = limiter.run(start, end, kBox, {Eigen::Isometry3d::Identity()});
  EXPECT_EQ(r.stop_reason, StepLimitStop::kPulledBack) << toString(r.stop_reason);
  EXPECT_DOUBLE_EQ(r.full_excess_mm, 2.0);  // capped at 4 × 0.5
  EXPECT_LE(r.excess_mm, 0.0);
  EXPECT_GT(r.pull_edits, 0);
  EXPECT_LE(r.pull_rounds, limitOf(0.5).max_pull_rounds);
  const MeshDistance previous(extractFieldSurface(sphereWithBump(0.01), kBox, 0.25), false);
  const TriangleMesh pulled = extractFieldSurface(end, kBox, 0.25);
  double worst = 0.0;
  for (int v = 0; v < pulled.countVertices(); ++v)
    worst = std::max(worst, previous.calcUnsignedDistance(pulled.vertices_mm.col(v)));
  EXPECT_LE(worst, 0.5 + 0.1);  // the limit, and the two grids' chords
  EXPECT_NEAR(end.calcValue(Eigen::Vector3d(-10.0, 0.0, 0.0)), 0.0, 1e-3) << "the far side stays";
  EXPECT_EQ(end.getWeights()(0), start.getWeights()(0)) << "the edit is made where the bump is";
}

TEST(SurfaceStepLimiter, WithoutAPreviousSurfaceOrWhenOffNothingChanges) {
  const GaussianField start = sphereOfRadius(10.0);
  GaussianField end = sphereOfRadius(13.0);
  SurfaceStepLimiter fresh(limitOf(0.5), freeLimits(1));
  EXPECT_EQ(fresh.run(start, end, kBox, {}).stop_reason, StepLimitStop::kDisabled);
  SurfaceStepLimiter off(limitOf(0.0), freeLimits(1));
  off.setPreviousSurface(start, kBox);
  EXPECT_EQ(off.run(start, end, kBox, {}).stop_reason, StepLimitStop::kDisabled);
  EXPECT_DOUBLE_EQ(sphereRadius(end), 13.0);
}

TEST(SurfaceStepLimiter, BadInputNamesTheFault) {
  StepLimitSettings rounds = limitOf(0.5);
  rounds.max_pull_rounds = -1;
  EXPECT_THROW(SurfaceStepLimiter(rounds, freeLimits(1)), std::invalid_argument);
  EXPECT_THROW(SurfaceStepLimiter(limitOf(0.5), WeightEditLimits{{true, true}, Eigen::VectorXd::Ones(1)}), std::invalid_argument);
  StepLimitSettings s = limitOf(0.5);
  s.cell_mm = 0.0;
  EXPECT_THROW(SurfaceStepLimiter(s, freeLimits(1)), std::invalid_argument);
  s = limitOf(0.5);
  s.max_trials = 0;
  try {
    SurfaceStepLimiter(s, freeLimits(1));
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("max_trials"), std::string::npos);
  }
  SurfaceStepLimiter limiter(limitOf(0.5), freeLimits(1));
  const GaussianField start = sphereOfRadius(10.0);
  limiter.setPreviousSurface(start, kBox);
  GaussianField other = test::makeRodField();
  EXPECT_THROW(limiter.run(start, other, kBox, {}), std::invalid_argument);
}

// In the deformer: a field disturbed by 4 mm per free centre is restored by the descent. With the
// limit, no point of a frame's surface is further from the previous frame's than 0.5 mm (the bones
// are still), checked on independent meshes; without it the first frame jumps by more.
TEST(SurfaceStepLimiter, TheDeformerRestoresADisturbedFieldOverFramesWithoutJumps) {
  const GaussianField field = test::makeRodField();
  const Attachments attachments = test::makeRodAttachments(field);
  const std::vector<Eigen::Isometry3d> still(2, Eigen::Isometry3d::Identity());
  const auto largestMove = [](const MuscleDeformer& d, const TriangleMesh& before) {
    const TriangleMesh after = d.extractSurface(0.5);
    const MeshDistance previous(before);
    double worst = 0.0;
    for (int v = 0; v < after.countVertices(); ++v)
      worst = std::max(worst, previous.calcUnsignedDistance(after.vertices_mm.col(v)));
    return worst;
  };
  const auto run = [&](double max_step_mm, int frames, double& first_move_mm, double& worst_move_mm) {
    DeformerSettings settings;
    settings.step_limit = limitOf(max_step_mm);
    MuscleDeformer d(field, attachments, settings);
    d.update(still);
    d.setCurrentCentres(test::perturbFreeCentres(d.getField().getCentres(), attachments, 4.0, 7));
    worst_move_mm = 0.0;
    for (int k = 0; k < frames; ++k) {
      const TriangleMesh before = d.extractSurface(0.5);
      const DeformResult& r = d.update(still);
      EXPECT_TRUE(std::isfinite(r.volume_ratio));
      const double move = largestMove(d, before);
      if (k == 0) first_move_mm = move;
      worst_move_mm = std::max(worst_move_mm, move);
    }
    return d.extractSurface(0.5);
  };
  double free_first = 0.0, free_worst = 0.0, limited_first = 0.0, limited_worst = 0.0;
  const TriangleMesh unlimited = run(0.0, 1, free_first, free_worst);
  const TriangleMesh limited = run(0.5, 30, limited_first, limited_worst);
  EXPECT_GT(free_first, 1.0);
  EXPECT_LE(limited_worst, 0.5 + 0.05);
  // Over the frames the limited run reaches what the unlimited one did at once.
  EXPECT_LE(test::calcMeanSurfaceDistance(limited, unlimited), 0.25);
}

}  // namespace
}  // namespace rbfmuscle
