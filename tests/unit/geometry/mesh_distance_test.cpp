// SPDX-License-Identifier: Apache-2.0
#include "geometry/mesh_distance.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "geometry/mesh_io.h"
#include "support/eigen_compare.h"
#include "unit/geometry/test_meshes.h"

namespace rbfmuscle {
namespace {

using test::modelPath;

// models/shapes/box.ply: x, z ∈ [−50, 50] mm, y ∈ [10, 90] mm.
const Eigen::Vector3d kBoxCentre(0, 50, 0), kBoxHalf(50, 40, 50);

/// Exact signed distance to the box (negative inside).
double boxDistance(const Eigen::Vector3d& p) {
  const Eigen::Vector3d q = (p - kBoxCentre).cwiseAbs() - kBoxHalf;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

Eigen::Matrix3Xd randomPoints(int n, const Eigen::AlignedBox3d& box, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Eigen::Matrix3Xd p(3, n);
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) p(k, i) = box.min()[k] + u(rng) * box.sizes()[k];
  return p;
}

class BoxDistance : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { distance_ = new MeshDistance(loadMesh(modelPath("shapes/box.ply"))); }
  static void TearDownTestSuite() { delete distance_; }
  static MeshDistance* distance_;
};
MeshDistance* BoxDistance::distance_ = nullptr;

TEST_F(BoxDistance, MatchesAnalyticNearFacesEdgesAndCorners) {
  std::vector<Eigen::Vector3d> points;
  for (double d : {-30.0, -5.0, -0.3, -1e-3, 1e-3, 0.3, 5.0, 30.0}) {
    points.push_back(kBoxCentre + Eigen::Vector3d(50 + d, 3, -7));           // face x
    points.push_back(kBoxCentre + Eigen::Vector3d(11, -40 - d, 20));         // face −y
    points.push_back(kBoxCentre + Eigen::Vector3d(50 + d, 40 + d, 12));      // edge
    points.push_back(kBoxCentre + Eigen::Vector3d(-50 - d, 40 + d, 50 + d)); // corner
    points.push_back(kBoxCentre + Eigen::Vector3d(50 + d, 40 + 0.5 * d, -50 - 2 * d));
  }
  for (const Eigen::Vector3d& p : points) {
    EXPECT_NEAR(distance_->calcSignedDistance(p), boxDistance(p), 1e-5) << p.transpose();
    EXPECT_NEAR(distance_->calcUnsignedDistance(p), std::abs(boxDistance(p)), 1e-5) << p.transpose();
    EXPECT_EQ(distance_->isInside(p), boxDistance(p) < 0) << p.transpose();
  }
}

TEST_F(BoxDistance, ClosestPointLiesOnSurfaceAtTheDistance) {
  const Eigen::Vector3d p(80, 120, -70);  // beyond the corner (50, 90, −50)
  const ClosestPoint c = distance_->findClosestPoint(p);
  EXPECT_TRUE(test::isApprox(c.point_mm, Eigen::Vector3d(50, 90, -50), 0, 1e-5));
  EXPECT_NEAR(c.distance_mm, (p - c.point_mm).norm(), 1e-12);
  ASSERT_GE(c.triangle, 0);
  ASSERT_LT(c.triangle, distance_->getMesh().countTriangles());
}

TEST_F(BoxDistance, SignCorrectOnRandomPointsAndBatchEqualsSingle) {
  const Eigen::Matrix3Xd p =
      randomPoints(10000, Eigen::AlignedBox3d(Eigen::Vector3d(-70, -10, -70), Eigen::Vector3d(70, 110, 70)), 7);
  const Eigen::VectorXd s = distance_->calcSignedDistances(p);
  const Eigen::VectorXd u = distance_->calcUnsignedDistances(p);
  const auto inside = distance_->calcInside(p);
  int wrong = 0;
  for (int i = 0; i < p.cols(); ++i) {
    const double exact = boxDistance(p.col(i));
    wrong += (s[i] < 0) != (exact < 0) ? 1 : 0;
    EXPECT_NEAR(s[i], exact, 1e-5);
    EXPECT_EQ(s[i], distance_->calcSignedDistance(p.col(i)));  // same bits with any threads
    EXPECT_EQ(u[i], std::abs(s[i]));
    EXPECT_EQ(inside[i], s[i] < 0);
  }
  EXPECT_EQ(wrong, 0);
}

TEST_F(BoxDistance, SignedClosestPointWithinAMaximumDistanceOrNone) {
  const Eigen::Matrix3Xd p =
      randomPoints(2000, Eigen::AlignedBox3d(Eigen::Vector3d(-80, -40, -80), Eigen::Vector3d(80, 140, 80)), 11);
  const double max_mm = 12.0;
  int found = 0, none = 0;
  for (int i = 0; i < p.cols(); ++i) {
    const double exact = distance_->calcSignedDistance(p.col(i));
    const SignedClosestPoint all = distance_->findSignedClosestPoint(p.col(i));
    EXPECT_EQ(all.signed_distance_mm, exact);  // the same descent and sign as calcSignedDistance
    EXPECT_EQ(all.point_mm, distance_->findClosestPoint(p.col(i)).point_mm);
    const SignedClosestPoint near = distance_->findSignedClosestPoint(p.col(i), max_mm);
    if (std::abs(exact) < max_mm) {
      ++found;
      EXPECT_EQ(near.signed_distance_mm, exact) << p.col(i).transpose();
      EXPECT_EQ(near.triangle, all.triangle);
    } else {
      ++none;
      EXPECT_EQ(near.triangle, -1) << p.col(i).transpose();
      EXPECT_EQ(near.distance_mm, std::numeric_limits<double>::infinity());
    }
  }
  EXPECT_GT(found, 100);  // both cases are exercised
  EXPECT_GT(none, 100);
}

TEST(MeshDistance, SphereWithinTessellationError) {
  const double R = 30.0;
  const TriangleMesh sphere = test::makeIcosphere(R, 4);
  // Deviation of the inscribed polyhedron from the sphere: R − nearest face plane.
  double min_plane = R;
  for (int t = 0; t < sphere.countTriangles(); ++t) {
    const Eigen::Vector3d a = sphere.getCorner(t, 0);
    const Eigen::Vector3d n = (sphere.getCorner(t, 1) - a).cross(sphere.getCorner(t, 2) - a).normalized();
    min_plane = std::min(min_plane, std::abs(n.dot(a)));
  }
  const double tol = R - min_plane + 1e-9;
  ASSERT_LT(tol, 0.05);
  const MeshDistance distance(sphere);
  const Eigen::Matrix3Xd p =
      randomPoints(10000, Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-45), Eigen::Vector3d::Constant(45)), 11);
  const Eigen::VectorXd s = distance.calcSignedDistances(p);
  int sign_checked = 0;
  for (int i = 0; i < p.cols(); ++i) {
    const double exact = p.col(i).norm() - R;
    EXPECT_NEAR(s[i], exact, tol) << p.col(i).transpose();
    if (std::abs(exact) > tol) {
      EXPECT_EQ(s[i] < 0, exact < 0) << p.col(i).transpose();
      ++sign_checked;
    }
  }
  EXPECT_GT(sign_checked, 9900);
  // Points on the sphere's vertices and just off them (vertex pseudo-normal region).
  for (int v = 0; v < sphere.countVertices(); v += 97) {
    const Eigen::Vector3d x = sphere.vertices_mm.col(v);
    EXPECT_LT(distance.calcSignedDistance(x * (1 - 1e-6)), 0.0);
    EXPECT_GT(distance.calcSignedDistance(x * (1 + 1e-6)), 0.0);
  }
}

TEST(MeshDistance, GluteusSignAgreesWithRayParity) {
  const TriangleMesh m = loadMesh(modelPath("hip/meshes/gluteus_maximus_r.ply"));
  const MeshDistance distance(m);
  const Eigen::AlignedBox3d box = m.calcBoundingBox();
  const Eigen::Matrix3Xd p = randomPoints(300, box, 3);
  const Eigen::VectorXd s = distance.calcSignedDistances(p);
  // Reference inside test: parity of crossings of a ray along a fixed odd direction.
  const Eigen::Vector3d dir = Eigen::Vector3d(0.2113, 0.5774, 0.7887).normalized();
  for (int i = 0; i < p.cols(); ++i) {
    if (std::abs(s[i]) < 1e-3) continue;
    int crossings = 0;
    for (int t = 0; t < m.countTriangles(); ++t) {
      const Eigen::Vector3d a = m.getCorner(t, 0), e1 = m.getCorner(t, 1) - a, e2 = m.getCorner(t, 2) - a;
      const Eigen::Vector3d h = dir.cross(e2);
      const double det = e1.dot(h);
      if (std::abs(det) < 1e-14) continue;
      const Eigen::Vector3d sv = p.col(i) - a;
      const double u = sv.dot(h) / det;
      const Eigen::Vector3d q = sv.cross(e1);
      const double v = dir.dot(q) / det;
      const double t_ray = e2.dot(q) / det;
      crossings += (u >= 0 && v >= 0 && u + v <= 1 && t_ray > 0) ? 1 : 0;
    }
    EXPECT_EQ(s[i] < 0, crossings % 2 == 1) << p.col(i).transpose() << " s=" << s[i];
  }
}

TEST(MeshDistance, RejectsEmptyMesh) {
  EXPECT_THROW(MeshDistance(TriangleMesh{}), MeshError);
}

}  // namespace
}  // namespace rbfmuscle
