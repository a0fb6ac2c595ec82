// SPDX-License-Identifier: Apache-2.0
#include "geometry/iso_surface.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "geometry/mesh_check.h"
#include "geometry/mesh_distance.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_measures.h"
#include "unit/geometry/test_meshes.h"

namespace rbfmuscle {
namespace {

/// f = R² − |x − c|² (positive inside the sphere).
ScalarFieldFn sphereField(double radius_mm, const Eigen::Vector3d& centre) {
  return [=](const Eigen::Matrix3Xd& p, Eigen::VectorXd& f) {
    f = radius_mm * radius_mm - (p.colwise() - centre).colwise().squaredNorm().array().transpose();
  };
}

TEST(IsoSurface, SphereIsOneWatertightOutwardComponentWithRightVolume) {
  const double R = 20.0;
  const Eigen::Vector3d c(3.3, -1.7, 802.4);  // far from the origin, off the grid
  const Eigen::AlignedBox3d box(c.array() - 24.0, c.array() + 24.0);
  const TriangleMesh m = extractIsoSurface(sphereField(R, c), box, 1.0);
  const MeshReport r = checkMesh(m);
  EXPECT_TRUE(r.isWatertight()) << r.describe();
  EXPECT_EQ(r.components, 1);
  EXPECT_TRUE(r.listProblems().empty()) << r.describe();
  const double exact = 4.0 / 3.0 * M_PI * R * R * R;
  EXPECT_NEAR(calcVolume(m), exact, 0.01 * exact);
  for (int v = 0; v < m.countVertices(); ++v)
    EXPECT_NEAR((m.vertices_mm.col(v) - c).norm(), R, 0.05) << v;
}

TEST(IsoSurface, FieldExactlyZeroOnGridNodesStaysManifold) {
  // Integer radius on an integer grid: nodes such as (10, 0, 0) and (6, 8, 0) have f = 0.
  const TriangleMesh m =
      extractIsoSurface(sphereField(10.0, Eigen::Vector3d::Zero()),
                        Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-12), Eigen::Vector3d::Constant(12)), 1.0);
  EXPECT_NO_THROW(validateMesh(m, "sphere iso-surface"));
  EXPECT_EQ(checkMesh(m).components, 1);
}

TEST(IsoSurface, TwoBlobsGiveTwoComponentsAndVerticesAreWelded) {
  const ScalarFieldFn two = [](const Eigen::Matrix3Xd& p, Eigen::VectorXd& f) {
    f.resize(p.cols());
    for (int i = 0; i < p.cols(); ++i)
      f[i] = std::max(25.0 - (p.col(i) - Eigen::Vector3d(-8, 0, 0)).squaredNorm(),
                      16.0 - (p.col(i) - Eigen::Vector3d(8, 0, 0)).squaredNorm());
  };
  const TriangleMesh m = extractIsoSurface(
      two, Eigen::AlignedBox3d(Eigen::Vector3d(-15, -7, -7), Eigen::Vector3d(15, 7, 7)), 0.7);
  const MeshReport r = checkMesh(m);
  EXPECT_EQ(r.components, 2);
  EXPECT_TRUE(r.listProblems().empty()) << r.describe();
  // Closed genus-0 pieces: V − E + F = 2 per component, E = 3F/2.
  EXPECT_EQ(m.countVertices() - m.countTriangles() / 2, 4);
}

TEST(IsoSurface, SignedDistanceOfGluteusReproducesItsVolume) {
  const TriangleMesh gluteus = loadMesh(test::modelPath("hip/meshes/gluteus_maximus_r.ply"));
  const MeshDistance distance(gluteus);
  const ScalarFieldFn inside_positive = [&](const Eigen::Matrix3Xd& p, Eigen::VectorXd& f) {
    f = -distance.calcSignedDistances(p);
  };
  const Eigen::AlignedBox3d box = gluteus.calcBoundingBox();
  const TriangleMesh m = extractIsoSurface(
      inside_positive, Eigen::AlignedBox3d(box.min().array() - 3.0, box.max().array() + 3.0), 1.5);
  EXPECT_TRUE(checkMesh(m).isWatertight());
  EXPECT_NEAR(calcVolume(m), calcVolume(gluteus), 0.02 * calcVolume(gluteus));
}

TEST(IsoSurface, BadArgumentsAndFieldsAreReported) {
  const auto field = sphereField(1.0, Eigen::Vector3d::Zero());
  const Eigen::AlignedBox3d box(Eigen::Vector3d::Constant(-2), Eigen::Vector3d::Constant(2));
  EXPECT_THROW(extractIsoSurface(field, box, 0.0), std::invalid_argument);
  EXPECT_THROW(extractIsoSurface(field, Eigen::AlignedBox3d(), 1.0), std::invalid_argument);
  EXPECT_THROW(extractIsoSurface(field, box, 1e-4), std::invalid_argument);  // 4e4³ nodes
  const ScalarFieldFn nan_field = [](const Eigen::Matrix3Xd& p, Eigen::VectorXd& f) {
    f = Eigen::VectorXd::Constant(p.cols(), std::nan(""));
  };
  try {
    extractIsoSurface(nan_field, box, 1.0);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("not finite"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rbfmuscle
