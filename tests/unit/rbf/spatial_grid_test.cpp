// SPDX-License-Identifier: Apache-2.0
/// SpatialGrid: queries equal a brute-force neighbour search (ascending),
/// before and after points move, on lattices with exact-distance ties, and
/// bad input is rejected with a message naming the value.
#include "rbf/spatial_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace rbfmuscle {
namespace {

std::vector<int> bruteForce(const Eigen::Matrix3Xd& points, const Eigen::Vector3d& p, double r) {
  std::vector<int> out;
  for (int i = 0; i < points.cols(); ++i)
    if ((points.col(i) - p).squaredNorm() <= r * r) out.push_back(i);
  return out;
}

/// Points in a box of half-side 50 mm, a tight cluster, and duplicates.
Eigen::Matrix3Xd makePoints(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> box(-50.0, 50.0);
  std::normal_distribution<double> cluster(10.0, 0.3);
  Eigen::Matrix3Xd points(3, n);
  for (int i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) points(a, i) = i % 5 == 0 ? cluster(rng) : box(rng);
  points.col(n - 1) = points.col(0);  // an exact duplicate
  return points;
}

void expectMatchesBruteForce(const SpatialGrid& grid, std::mt19937& rng) {
  const Eigen::Matrix3Xd& points = grid.getPoints();
  std::uniform_real_distribution<double> box(-70.0, 70.0);
  std::vector<int> found = {42, 7};  // stale content must be cleared
  for (double radius : {0.0, 0.7, 3.0, 12.0, 60.0, 400.0}) {
    for (int t = 0; t < 60; ++t) {
      Eigen::Vector3d p;
      if (t % 3 == 0)
        p = points.col(t % points.cols());  // exactly at a point
      else
        p = Eigen::Vector3d(box(rng), box(rng), box(rng));
      grid.findWithinRadius(p, radius, found);
      ASSERT_EQ(found, bruteForce(points, p, radius))
          << "radius " << radius << " at " << p.transpose();
    }
  }
}

TEST(SpatialGrid, QueryEqualsBruteForceForSeveralCellSizes) {
  std::mt19937 rng(1);
  const Eigen::Matrix3Xd points = makePoints(rng, 1500);
  for (double cell : {0.5, 2.0, 9.0, 100.0}) {
    SCOPED_TRACE("cell size " + std::to_string(cell));
    const SpatialGrid grid(points, cell);
    EXPECT_EQ(grid.getNumPoints(), 1500);
    expectMatchesBruteForce(grid, rng);
  }
}

TEST(SpatialGrid, UnorderedQueryAndCandidatesCoverTheBall) {
  std::mt19937 rng(3);
  const Eigen::Matrix3Xd points = makePoints(rng, 1200);
  const SpatialGrid grid(points, 3.0);
  std::uniform_real_distribution<double> box(-60.0, 60.0);
  std::vector<int> found;
  for (double radius : {1.0, 5.0, 20.0}) {
    for (int t = 0; t < 40; ++t) {
      const Eigen::Vector3d p(box(rng), box(rng), box(rng));
      const std::vector<int> expected = bruteForce(points, p, radius);
      grid.findWithinRadiusUnordered(p, radius, found);
      std::sort(found.begin(), found.end());
      ASSERT_EQ(found, expected);
      // Candidates: each point at most once, the ball included, the points
      // passed as they are stored.
      std::vector<int> seen(static_cast<std::size_t>(points.cols()), 0);
      grid.visitCandidates(p, radius, [&](int i, const auto& point) {
        ++seen[static_cast<std::size_t>(i)];
        EXPECT_TRUE(Eigen::Vector3d(point) == points.col(i));
      });
      for (int i = 0; i < points.cols(); ++i) ASSERT_LE(seen[static_cast<std::size_t>(i)], 1);
      for (int i : expected) ASSERT_EQ(seen[static_cast<std::size_t>(i)], 1) << "point " << i;
    }
  }
}

TEST(SpatialGrid, UpdateAfterPointsMoveEqualsBruteForce) {
  std::mt19937 rng(2);
  Eigen::Matrix3Xd points = makePoints(rng, 800);
  SpatialGrid grid(points, 4.0);
  std::normal_distribution<double> step(0.0, 2.0);
  for (int round = 0; round < 3; ++round) {
    for (int i = 0; i < points.cols(); ++i)
      for (int a = 0; a < 3; ++a) points(a, i) += step(rng);
    grid.update(points);
    expectMatchesBruteForce(grid, rng);
  }
  // A different count rebuilds.
  const Eigen::Matrix3Xd fewer = points.leftCols(100);
  grid.update(fewer);
  EXPECT_EQ(grid.getNumPoints(), 100);
  expectMatchesBruteForce(grid, rng);
}

TEST(SpatialGrid, LatticeTiesAtExactRadiusAreIncluded) {
  // Integer lattice with cell size 1: points lie on cell boundaries and the
  // six axis neighbours are at distance exactly 1.
  Eigen::Matrix3Xd points(3, 125);
  int i = 0;
  for (int z = -2; z <= 2; ++z)
    for (int y = -2; y <= 2; ++y)
      for (int x = -2; x <= 2; ++x) points.col(i++) = Eigen::Vector3d(x, y, z);
  const SpatialGrid grid(points, 1.0);
  std::vector<int> found;
  grid.findWithinRadius(Eigen::Vector3d::Zero(), 1.0, found);
  EXPECT_EQ(found, (std::vector<int>{37, 57, 61, 62, 63, 67, 87}));
  grid.findWithinRadius(Eigen::Vector3d(2, 2, 2), 0.0, found);
  EXPECT_EQ(found, std::vector<int>{124});
}

TEST(SpatialGrid, EmptyGridNegativeRadiusAndFarQueriesFindNothing) {
  std::vector<int> found = {1};
  SpatialGrid empty;
  empty.findWithinRadius(Eigen::Vector3d::Zero(), 10.0, found);
  EXPECT_TRUE(found.empty());
  const SpatialGrid grid(Eigen::Matrix3Xd::Zero(3, 4), 1.0);
  grid.findWithinRadius(Eigen::Vector3d::Zero(), -1.0, found);
  EXPECT_TRUE(found.empty());
  grid.findWithinRadius(Eigen::Vector3d(1e300, 0, 0), 1.0, found);
  EXPECT_TRUE(found.empty());
  grid.findWithinRadius(Eigen::Vector3d(1e300, 0, 0), 1e301, found);
  EXPECT_EQ(found, (std::vector<int>{0, 1, 2, 3}));
}

TEST(SpatialGrid, RejectsBadInputNamingTheValue) {
  const Eigen::Matrix3Xd points = Eigen::Matrix3Xd::Zero(3, 3);
  try {
    SpatialGrid grid(points, 0.0);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cell size 0"), std::string::npos) << e.what();
  }
  Eigen::Matrix3Xd bad = points;
  bad(1, 2) = std::numeric_limits<double>::quiet_NaN();
  try {
    SpatialGrid grid(bad, 1.0);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("point 2 = (  0 nan   0)"), std::string::npos) << e.what();
  }
  const SpatialGrid grid(points, 1.0);
  std::vector<int> found;
  EXPECT_THROW(grid.findWithinRadius(Eigen::Vector3d(0, INFINITY, 0), 1.0, found),
               std::invalid_argument);
}

}  // namespace
}  // namespace rbfmuscle
