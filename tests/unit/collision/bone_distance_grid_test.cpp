// SPDX-License-Identifier: Apache-2.0
/// BoneDistanceGrid against MeshDistance: exact on planes, within the stated error near a
/// sphere, a box and the femur, gradient of the interpolant, far answers as bounds, bricks
/// built lazily, same bits for any thread count and order, bad input.
#include "collision/bone_distance_grid.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "geometry/mesh_distance.h"
#include "geometry/mesh_io.h"
#include "support/eigen_compare.h"
#include "unit/collision/grid_error.h"
#include "unit/geometry/test_meshes.h"

namespace rbfmuscle {
namespace {

using test::isApprox;

/// Cube [−half, half]³ (mm) turned by a rotation about a skew axis: faces not on grid planes.
TriangleMesh tiltedCube(double half_mm, const Eigen::Matrix3d& R) {
  TriangleMesh mesh = test::makeCube(2 * half_mm, -half_mm);
  mesh.vertices_mm = R * mesh.vertices_mm;
  return mesh;
}

Eigen::Matrix3d someRotation() { return Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix(); }

/// Uniformly random points (mm) in `box`, fixed seed.
Eigen::Matrix3Xd randomPointsIn(const Eigen::AlignedBox3d& box, int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Eigen::Matrix3Xd p(3, n);
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) p(k, i) = box.min()(k) + unit(rng) * box.sizes()(k);
  return p;
}

// The errors stated in bone_distance_grid.h (h = 1 mm, band 6 mm), with some room.
constexpr double kSphereMaxError_mm = 0.04;
constexpr double kBoxMaxError_mm = 0.5;
constexpr double kFemurMaxError_mm = 0.5;

/// Runs `f` and expects a CollisionError whose message contains `what`.
template <typename F>
void expectCollisionError(F&& f, const std::string& what) {
  try {
    f();
    ADD_FAILURE() << "no CollisionError; expected one naming '" << what << "'";
  } catch (const CollisionError& e) {
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

/// Bitwise equality of two samples.
bool sameBits(const BoneDistanceSample& a, const BoneDistanceSample& b) {
  return std::memcmp(&a.value_mm, &b.value_mm, sizeof(double)) == 0 &&
         std::memcmp(a.gradient_B.data(), b.gradient_B.data(), 3 * sizeof(double)) == 0 && a.near == b.near;
}

void recordError(const std::string& name, const test::GridError& e) {
  ::testing::Test::RecordProperty(name + "_mean_mm", std::to_string(e.mean_mm));
  ::testing::Test::RecordProperty(name + "_p99_mm", std::to_string(e.p99_mm));
  ::testing::Test::RecordProperty(name + "_max_mm", std::to_string(e.max_mm));
}

TEST(BoneDistanceGrid, PlaneIsInterpolatedExactly) {
  // Near the middle of a face of a large tilted cube every node's closest feature is that
  // face, so s is linear there and the trilinear interpolant reproduces it.
  const Eigen::Matrix3d R = someRotation();
  const BoneDistanceGrid grid(tiltedCube(100.0, R));
  const Eigen::Vector3d normal = R.col(2);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> along(-20.0, 20.0), offset(-3.0, 3.0);
  for (int i = 0; i < 500; ++i) {
    const double d = offset(rng);
    const Eigen::Vector3d p = R * Eigen::Vector3d(along(rng), along(rng), 100.0 + d);
    const BoneDistanceSample s = grid.sample(p);
    ASSERT_TRUE(s.near);
    EXPECT_NEAR(s.value_mm, d, 1e-9) << p.transpose();
    EXPECT_TRUE(isApprox(s.gradient_B, normal, 0.0, 1e-9)) << p.transpose();
  }
}

TEST(BoneDistanceGrid, SphereValuesAreWithinTheStatedErrorOfMeshDistance) {
  const BoneDistanceGrid grid(test::makeIcosphere(20.0, 4));
  const test::GridError e = test::measureGridError(grid, test::sampleNearSurface(grid.getMeshDistance().getMesh(), 5000, 3.0, 2),
                                                    kSphereMaxError_mm);
  recordError("sphere", e);
  EXPECT_EQ(e.not_near, 0);
  EXPECT_EQ(e.wrong_sign, 0);
  EXPECT_LT(e.max_mm, kSphereMaxError_mm);
}

TEST(BoneDistanceGrid, BoxValuesAreWithinTheStatedErrorAtSharpEdges) {
  const BoneDistanceGrid grid(tiltedCube(20.0, someRotation()));
  const test::GridError e = test::measureGridError(grid, test::sampleNearSurface(grid.getMeshDistance().getMesh(), 5000, 3.0, 3),
                                                    kBoxMaxError_mm);
  recordError("box", e);
  EXPECT_EQ(e.not_near, 0);
  EXPECT_EQ(e.wrong_sign, 0);
  EXPECT_LT(e.max_mm, kBoxMaxError_mm);
}

TEST(BoneDistanceGrid, FemurValuesAreWithinTheStatedErrorNearItsSurface) {
  const BoneDistanceGrid grid(loadMesh(test::modelPath("hip/meshes/femur_r.ply")));
  const test::GridError e = test::measureGridError(grid, test::sampleNearSurface(grid.getMeshDistance().getMesh(), 5000, 3.0, 4),
                                                    kFemurMaxError_mm);
  recordError("femur", e);
  EXPECT_EQ(e.not_near, 0);
  EXPECT_EQ(e.wrong_sign, 0);
  EXPECT_LT(e.max_mm, kFemurMaxError_mm);
}


TEST(BoneDistanceGrid, GradientMatchesFiniteDifferencesOfTheInterpolant) {
  const BoneDistanceGrid grid(test::makeIcosphere(20.0, 4));
  const Eigen::Matrix3Xd points = test::sampleNearSurface(grid.getMeshDistance().getMesh(), 500, 3.0, 5);
  const Eigen::Vector3d origin = grid.getGridBox().min();
  const double h = grid.getSettings().spacing_mm, step = 1e-6;
  int checked = 0;
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    const Eigen::Vector3d p = points.col(i);
    // The gradient jumps across cell faces: keep the difference stencil inside one cell.
    const Eigen::Array3d u = (p - origin).array() / h, frac = u - u.floor();
    if ((frac.min(1.0 - frac) < 1e-4).any()) continue;
    const BoneDistanceSample s = grid.sample(p);
    ASSERT_TRUE(s.near);
    Eigen::Vector3d fd;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d e = step * Eigen::Vector3d::Unit(k);
      fd(k) = (grid.sample(p + e).value_mm - grid.sample(p - e).value_mm) / (2 * step);
    }
    EXPECT_TRUE(isApprox(s.gradient_B, fd, 0.0, 1e-7)) << p.transpose();
    ++checked;
  }
  EXPECT_GT(checked, 400);
}

TEST(BoneDistanceGrid, GradientIsNearlyTheOutwardNormalNearASphere) {
  const BoneDistanceGrid grid(test::makeIcosphere(20.0, 4));
  const Eigen::Matrix3Xd points = test::sampleNearSurface(grid.getMeshDistance().getMesh(), 1000, 3.0, 6);
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    const Eigen::Vector3d p = points.col(i);
    EXPECT_TRUE(isApprox(grid.sample(p).gradient_B, p.normalized(), 0.0, 0.1)) << p.transpose();
  }
}

TEST(BoneDistanceGrid, FarPointsReportALowerBoundAndNoBrickIsBuilt) {
  const BoneDistanceGrid grid(test::makeIcosphere(20.0, 3));
  const double band = grid.getSettings().band_mm;
  std::mt19937 rng(7);
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> radius(60.0, 300.0);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d p = radius(rng) * Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
    ASSERT_FALSE(grid.getGridBox().contains(p));
    const BoneDistanceSample s = grid.sample(p);
    EXPECT_FALSE(s.near);
    EXPECT_TRUE(s.gradient_B.isZero(0.0));
    EXPECT_GE(s.value_mm, band);
    EXPECT_LE(s.value_mm, grid.getMeshDistance().calcSignedDistance(p));
  }
  const BoneDistanceGridStats stats = grid.getStats();
  EXPECT_EQ(stats.bricks_near, 0);
  EXPECT_EQ(stats.bricks_far, 0);
  EXPECT_EQ(stats.nodes_stored, 0);
  EXPECT_EQ(stats.distance_queries, 0);
}

TEST(BoneDistanceGrid, DeepInsidePointsReportAnUpperBoundWithoutNodeEvaluations) {
  const BoneDistanceGrid grid(test::makeCube(200.0, -100.0));
  const double band = grid.getSettings().band_mm;
  const Eigen::Matrix3Xd points =
      randomPointsIn(Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-70), Eigen::Vector3d::Constant(70)), 300, 8);
  for (const Eigen::Vector3d& p : points.colwise()) {
    const BoneDistanceSample s = grid.sample(p);
    EXPECT_FALSE(s.near);
    EXPECT_EQ(s.value_mm, -band);
    EXPECT_TRUE(s.gradient_B.isZero(0.0));
    EXPECT_LE(grid.getMeshDistance().calcSignedDistance(p), -band);
  }
  EXPECT_GT(grid.getStats().bricks_far, 0);
  EXPECT_EQ(grid.getStats().bricks_near, 0);
  EXPECT_EQ(grid.getStats().nodes_stored, 0);
  EXPECT_EQ(grid.getStats().distance_queries, grid.getStats().bricks_far);  // one per brick centre
}

TEST(BoneDistanceGrid, BricksAreBuiltOnlyWhereQueriedAndOnlyOnce) {
  const BoneDistanceGrid grid(test::makeIcosphere(20.0, 3));
  const long long nodes_per_brick = 9 * 9 * 9;
  EXPECT_EQ(grid.getStats().bricks_near, 0);
  const Eigen::Vector3d p(20.0, 0.3, 0.2);
  const BoneDistanceSample first = grid.sample(p);
  EXPECT_EQ(grid.getStats().bricks_near, 1);
  EXPECT_EQ(grid.getStats().nodes_stored, nodes_per_brick);
  const long long queries = grid.getStats().distance_queries;
  EXPECT_GT(queries, 0);
  EXPECT_TRUE(sameBits(grid.sample(p), first));
  grid.sample(p + Eigen::Vector3d(0.1, 0.1, 0.1));  // same brick
  EXPECT_EQ(grid.getStats().bricks_near, 1);
  EXPECT_EQ(grid.getStats().distance_queries, queries);
  grid.sample(Eigen::Vector3d(-20.0, 0.3, 0.2));  // another brick
  EXPECT_EQ(grid.getStats().bricks_near, 2);
  EXPECT_EQ(grid.getStats().nodes_stored, 2 * nodes_per_brick);
  EXPECT_EQ(grid.getStats().bricks_far, 0);
  EXPECT_EQ(grid.getStats().brick_slots, 7 * 7 * 7);  // (40 + 2·6) / 8 → 7 bricks per axis
}

TEST(BoneDistanceGrid, ValueIsContinuousAcrossCellsBricksTheBandAndTheGridBox) {
  // A line from far outside the grid box through the centre of a sphere (far inside).
  const BoneDistanceGrid grid(test::makeIcosphere(20.0, 3));
  const Eigen::Vector3d a(-60.0, -7.0, -3.3), b(60.0, 9.0, 4.1);
  const int steps = 20000;
  const double step_mm = (b - a).norm() / steps;
  double previous = grid.sample(a).value_mm;
  int near = 0, far_inside = 0, far_outside = 0;
  for (int i = 1; i <= steps; ++i) {
    const BoneDistanceSample s = grid.sample(a + (b - a) * (double(i) / steps));
    // The interpolant's gradient has components within ±1 (differences of a 1-Lipschitz s).
    ASSERT_LE(std::abs(s.value_mm - previous), std::sqrt(3.0) * step_mm + 1e-12) << i;
    previous = s.value_mm;
    (s.near ? near : s.value_mm < 0 ? far_inside : far_outside)++;
  }
  EXPECT_GT(near, 0);
  EXPECT_GT(far_inside, 0);
  EXPECT_GT(far_outside, 0);
}

TEST(BoneDistanceGrid, AnswersAreBoundsAndSignsAreRightAnywhereAroundTheBone) {
  const BoneDistanceGrid grid(tiltedCube(20.0, someRotation()));
  const double band = grid.getSettings().band_mm;
  Eigen::AlignedBox3d around = grid.getGridBox();
  around.extend(around.min() - Eigen::Vector3d::Constant(10)).extend(around.max() + Eigen::Vector3d::Constant(10));
  const Eigen::Matrix3Xd points = randomPointsIn(around, 5000, 9);
  for (const Eigen::Vector3d& p : points.colwise()) {
    const BoneDistanceSample s = grid.sample(p);
    const double exact = grid.getMeshDistance().calcSignedDistance(p);
    if (s.near) {
      EXPECT_NEAR(s.value_mm, exact, kBoxMaxError_mm);
    } else if (s.value_mm > 0) {
      EXPECT_GE(s.value_mm, band);
      EXPECT_GE(exact, s.value_mm - kBoxMaxError_mm) << p.transpose();  // ≥ band up to the interpolation error
    } else {
      EXPECT_EQ(s.value_mm, -band);
      EXPECT_LE(exact, -band + kBoxMaxError_mm) << p.transpose();
    }
    if (std::abs(exact) > kBoxMaxError_mm) {
      EXPECT_GT(s.value_mm * exact, 0.0) << p.transpose();
    }
  }
}

TEST(BoneDistanceGrid, SameValuesForAnyThreadCountAndOrder) {
  const TriangleMesh sphere = test::makeIcosphere(20.0, 3);
  Eigen::Matrix3Xd points(3, 3000);
  points << test::sampleNearSurface(sphere, 2000, 8.0, 10),
      randomPointsIn(Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-40), Eigen::Vector3d::Constant(40)), 1000, 11);
  const auto n = std::size_t(points.cols());
  std::vector<BoneDistanceSample> reference(n);
  const BoneDistanceGrid serial(sphere);
  for (std::size_t i = 0; i < n; ++i) reference[i] = serial.sample(points.col(Eigen::Index(i)));

  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::mt19937 rng(12);
#ifdef _OPENMP
  const int threads_before = omp_get_max_threads();
#endif
  for (int threads : {1, 2, 4}) {
#ifdef _OPENMP
    omp_set_num_threads(threads);
#endif
    std::shuffle(order.begin(), order.end(), rng);
    const BoneDistanceGrid grid(sphere);  // fresh: bricks built by whichever thread comes first
    std::vector<BoneDistanceSample> out(n);
#pragma omp parallel for schedule(dynamic, 16)
    for (std::ptrdiff_t k = 0; k < std::ptrdiff_t(n); ++k) {
      const std::size_t i = order[std::size_t(k)];
      out[i] = grid.sample(points.col(Eigen::Index(i)));
    }
    for (std::size_t i = 0; i < n; ++i) ASSERT_TRUE(sameBits(out[i], reference[i])) << threads << " threads, point " << i;
    EXPECT_EQ(grid.getStats().bricks_near, serial.getStats().bricks_near) << "each brick built once";
    EXPECT_EQ(grid.getStats().bricks_far, serial.getStats().bricks_far);
  }
#ifdef _OPENMP
  omp_set_num_threads(threads_before);
#endif
}

TEST(BoneDistanceGrid, BuildingAllBricksFirstGivesTheSameAnswers) {
  const TriangleMesh sphere = test::makeIcosphere(20.0, 3);
  const BoneDistanceGrid lazy(sphere), eager(sphere);
  eager.buildAllBricks();
  const BoneDistanceGridStats stats = eager.getStats();
  EXPECT_EQ(stats.bricks_near + stats.bricks_far, stats.brick_slots);
  EXPECT_GT(stats.bricks_far, 0);
  Eigen::Matrix3Xd points(3, 2000);
  points << test::sampleNearSurface(sphere, 1000, 8.0, 13),
      randomPointsIn(Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-40), Eigen::Vector3d::Constant(40)), 1000, 14);
  for (Eigen::Index i = 0; i < points.cols(); ++i)
    ASSERT_TRUE(sameBits(eager.sample(points.col(i)), lazy.sample(points.col(i)))) << "point " << i;
  EXPECT_EQ(eager.getStats().bricks_near, stats.bricks_near) << "nothing left to build";
}

TEST(BoneDistanceGrid, BadInputGivesAnExceptionNamingTheProblem) {
  const TriangleMesh sphere = test::makeIcosphere(10.0, 1);
  expectCollisionError([] { BoneDistanceGrid grid{TriangleMesh{}}; }, "no triangles");
  TriangleMesh broken = sphere;
  broken.vertices_mm(0, 0) = std::numeric_limits<double>::quiet_NaN();
  expectCollisionError([&] { BoneDistanceGrid grid(broken); }, "non-finite");
  expectCollisionError([] { BoneDistanceGrid grid{std::shared_ptr<const MeshDistance>()}; }, "null");
  expectCollisionError([&] { BoneDistanceGrid grid(std::make_shared<const MeshDistance>(sphere, false)); }, "signs");
  for (double h : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    BoneDistanceGridSettings settings;
    settings.spacing_mm = h;
    expectCollisionError([&] { BoneDistanceGrid grid(sphere, settings); }, "spacing_mm");
  }
  BoneDistanceGridSettings settings;
  settings.band_mm = 0.0;
  expectCollisionError([&] { BoneDistanceGrid grid(sphere, settings); }, "band_mm");
  settings = {};
  settings.brick_cells = 0;
  expectCollisionError([&] { BoneDistanceGrid grid(sphere, settings); }, "brick_cells");
  settings = {};
  settings.spacing_mm = 1e-3;
  expectCollisionError([&] { BoneDistanceGrid grid(sphere, settings); }, "slots");

  const BoneDistanceGrid grid(sphere);
  for (double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()})
    expectCollisionError([&] { grid.sample(Eigen::Vector3d(0.0, bad, 1.0)); }, "not finite");
}

}  // namespace
}  // namespace rbfmuscle
