// SPDX-License-Identifier: Apache-2.0
/// Putting a carried vertex onto f = 0 on analytic fields: from inside along its normal, also to
/// the farther face of a thin slab when the normal says so; from outside to the nearest surface
/// whatever the normal; and the ray search that finds no crossing within its reach.
#include "pipeline/surface_projection.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace rbfmuscle {
namespace {

/// The half-space below z = 0 as a signed distance: f = −z (inside where z < 0).
class HalfSpace final : public ImplicitField {
 public:
  double calcValue(const Eigen::Vector3d& p) const override { return -p.z(); }
  Eigen::Vector3d calcGradient(const Eigen::Vector3d&) const override { return -Eigen::Vector3d::UnitZ(); }
};

/// A slab 2 mm thick, |z| < 1: f = 1 − |z|.
class Slab final : public ImplicitField {
 public:
  double calcValue(const Eigen::Vector3d& p) const override { return 1.0 - std::abs(p.z()); }
  Eigen::Vector3d calcGradient(const Eigen::Vector3d& p) const override {
    return p.z() > 0.0 ? Eigen::Vector3d(-Eigen::Vector3d::UnitZ()) : Eigen::Vector3d::UnitZ();
  }
};

/// A ball of radius 10 mm about the origin: f = 10 − ‖p‖.
class Ball final : public ImplicitField {
 public:
  double calcValue(const Eigen::Vector3d& p) const override { return 10.0 - p.norm(); }
  Eigen::Vector3d calcGradient(const Eigen::Vector3d& p) const override { return -p.normalized(); }
};

const double kTilt = M_PI / 6.0;  // 30°
const Eigen::Vector3d kTilted(std::sin(kTilt), 0.0, std::cos(kTilt));

TEST(ProjectVertex, FromInsideGoesOutAlongItsNormal) {
  const SurfaceSettings settings;
  Eigen::Vector3d p(0, 0, -1);  // 1 mm inside
  double start = 0.0;
  const FieldSample at = projectVertex(HalfSpace(), 3.0 * kTilted, p, settings, start);
  EXPECT_DOUBLE_EQ(start, 1.0);
  EXPECT_LE(std::abs(at.value), settings.tolerance);
  // On the normal's line, 1/cos 30° from the start, not at the nearest point (0, 0, 0).
  EXPECT_NEAR(p.x(), std::tan(kTilt), 1e-3);
  EXPECT_NEAR(p.y(), 0.0, 1e-12);
}

TEST(ProjectVertex, FromInsideAThinSheetTakesTheFaceItsNormalNamesNotTheNearerOne) {
  const SurfaceSettings settings;
  Eigen::Vector3d p(0, 0, 0.2);  // nearer the upper face; the tissue says it belongs to the lower
  double start = 0.0;
  projectVertex(Slab(), -Eigen::Vector3d::UnitZ(), p, settings, start);
  EXPECT_NEAR(p.z(), -1.0, settings.tolerance);
  Eigen::Vector3d q(0, 0, 0.2);
  projectByNewton(Slab(), Slab().calcSample(q), q, settings);  // what the gradient alone does
  EXPECT_NEAR(q.z(), 1.0, settings.tolerance);
}

TEST(ProjectVertex, FromOutsideGoesToTheNearestSurfaceWhateverItsNormal) {
  const SurfaceSettings settings;
  Eigen::Vector3d p(0, 0, 1);
  double start = 0.0;
  const FieldSample at = projectVertex(HalfSpace(), kTilted, p, settings, start);
  EXPECT_DOUBLE_EQ(start, -1.0);
  EXPECT_LE(std::abs(at.value), settings.tolerance);
  EXPECT_TRUE(p.isApprox(Eigen::Vector3d(0, 0, 0), 1e-9)) << p.transpose();
}

TEST(ProjectVertex, FromInsideWithoutACrossingOnItsNormalTakesTheNewtonPoint) {
  const SurfaceSettings settings;
  Eigen::Vector3d p(0, 0, -1);
  double start = 0.0;
  projectVertex(HalfSpace(), Eigen::Vector3d::UnitX(), p, settings, start);  // runs along the surface
  EXPECT_TRUE(p.isApprox(Eigen::Vector3d(0, 0, 0), 1e-9)) << p.transpose();
  Eigen::Vector3d q(0, 0, -1);
  projectVertex(HalfSpace(), Eigen::Vector3d::Zero(), q, settings, start);  // no normal
  EXPECT_TRUE(q.isApprox(Eigen::Vector3d(0, 0, 0), 1e-9)) << q.transpose();
}

TEST(ProjectVertex, FromInsideGoesOutAlongItsNormalOntoACurvedSurface) {
  const SurfaceSettings settings;
  const Eigen::Vector3d start_point(1.0, 0.5, 8.0);  // 1.9 mm inside the ball
  Eigen::Vector3d p = start_point;
  double start = 0.0;
  projectVertex(Ball(), kTilted, p, settings, start);
  EXPECT_NEAR(p.norm(), 10.0, settings.tolerance);
  EXPECT_NEAR((p - start_point).normalized().dot(kTilted), 1.0, 1e-9);  // on the ray along +n
}

TEST(ProjectAlongLine, LeavesThePointWhereNoCrossingLiesWithinItsReach) {
  const SurfaceSettings settings;
  Eigen::Vector3d p(0, 0, 1);
  FieldSample at = HalfSpace().calcSample(p);
  EXPECT_FALSE(projectAlongLine(HalfSpace(), Eigen::Vector3d::UnitX(), at, p, settings, 50.0));  // parallel
  EXPECT_FALSE(projectAlongLine(HalfSpace(), Eigen::Vector3d::UnitZ(), at, p, settings, 0.9));   // 1 mm away
  EXPECT_TRUE(p.isApprox(Eigen::Vector3d(0, 0, 1)));
  EXPECT_DOUBLE_EQ(at.value, -1.0);
  EXPECT_TRUE(projectAlongLine(HalfSpace(), Eigen::Vector3d::UnitZ(), at, p, settings, 1.1));
  EXPECT_NEAR(p.z(), 0.0, settings.tolerance);
  EXPECT_DOUBLE_EQ(at.value, HalfSpace().calcValue(p));
}

TEST(SurfaceSettings, BadValuesAreRefused) {
  SurfaceSettings settings;
  settings.newton_steps = 0;
  EXPECT_THROW(checkSurfaceSettings(settings), std::invalid_argument);
  settings = SurfaceSettings{};
  settings.max_step_mm = 0.0;
  EXPECT_THROW(checkSurfaceSettings(settings), std::invalid_argument);
  EXPECT_NO_THROW(checkSurfaceSettings(SurfaceSettings{}));
}

}  // namespace
}  // namespace rbfmuscle
