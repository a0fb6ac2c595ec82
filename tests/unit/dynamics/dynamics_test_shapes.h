// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Small analytic muscles for the dynamics tests, and the surface distance they are judged by.
#include "dynamics/attachment.h"
#include "geometry/mesh_distance.h"
#include "rbf/gaussian_field.h"

#include <Eigen/Core>

#include <cmath>
#include <random>

namespace rbfmuscle::test {

/// One Gaussian, surface a sphere of radius 10 mm: λ e^{−α r²} − 5 = 0 at r = 10 for α = 0.01.
inline GaussianField makeSphereField() {
  Eigen::Matrix3Xd xi = Eigen::Matrix3Xd::Zero(3, 1);
  return GaussianField(-5.0, xi, Eigen::VectorXd::Constant(1, 5.0 * std::exp(1.0)), Eigen::VectorXd::Constant(1, 0.01));
}

/// A rod-like "muscle" along x from about −38 to +38 mm: three rows (y = 0, ±4 mm)
/// of 13 Gaussians at x = −30 … 30 (spacing 5 mm), α = 0.02 mm⁻², λ = 2.5 (±10 %
/// deterministic variation so no symmetry hides a bug), b = −5 (the fit convention).
inline GaussianField makeRodField() {
  const int per_row = 13;
  Eigen::Matrix3Xd xi(3, 3 * per_row);
  Eigen::VectorXd lambda(3 * per_row), alpha(3 * per_row);
  int k = 0;
  for (int row = -1; row <= 1; ++row) {
    for (int i = 0; i < per_row; ++i, ++k) {
      xi.col(k) = Eigen::Vector3d(-30.0 + 5.0 * i, 4.0 * row, 0.5 * row * row);
      lambda(k) = 2.5 * (1.0 + 0.1 * std::sin(1.7 * k));
      alpha(k) = 0.02;
    }
  }
  return GaussianField(-5.0, xi, lambda, alpha);
}

/// A closed box mesh [lo, hi] (12 triangles, wound outward): a rest mesh for the rod.
inline TriangleMesh makeBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  TriangleMesh mesh;
  mesh.vertices_mm.resize(3, 8);
  for (int i = 0; i < 8; ++i)
    mesh.vertices_mm.col(i) = Eigen::Vector3d(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
  mesh.triangles.resize(3, 12);
  mesh.triangles << 0, 0, 4, 4, 0, 0, 2, 2, 0, 0, 1, 1,  //
      2, 3, 5, 7, 1, 5, 6, 7, 4, 6, 3, 7,               //
      3, 1, 7, 6, 5, 4, 7, 3, 6, 2, 7, 5;
  return mesh;
}

/// Bone 0 holds the rod's x < −22 mm end, bone 1 its x > 22 mm end (landmarks of radius 9 mm).
inline Attachments makeRodAttachments(const GaussianField& field) {
  Attachments a = makeFreeAttachments(field.getNumCentres(), 2);
  attachByLandmarks(field,
                    {AttachmentLandmark{0, Eigen::Vector3d(-30, 0, 0), 9.0},
                     AttachmentLandmark{1, Eigen::Vector3d(30, 0, 0), 9.0}},
                    a);
  return a;
}

/// Symmetric mean surface distance: the mean over the vertices of a of their distance
/// to b and over those of b to a, averaged (mm).
inline double calcMeanSurfaceDistance(const TriangleMesh& a, const TriangleMesh& b) {
  const MeshDistance da(a), db(b);
  const double ab = db.calcUnsignedDistances(a.vertices_mm).mean();
  const double ba = da.calcUnsignedDistances(b.vertices_mm).mean();
  return 0.5 * (ab + ba);
}

/// Moves every free centre by `distance_mm` in a random direction (fixed seed).
inline Eigen::Matrix3Xd perturbFreeCentres(const Eigen::Matrix3Xd& centres, const Attachments& a,
                                           double distance_mm, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::Matrix3Xd out = centres;
  for (Eigen::Index k = 0; k < centres.cols(); ++k) {
    Eigen::Vector3d dir(normal(rng), normal(rng), normal(rng));
    if (a.isAttached(static_cast<int>(k))) continue;
    out.col(k) += distance_mm * dir.normalized();
  }
  return out;
}

/// Rotation by `angle_rad` about the axis through `pivot_mm` along `axis`.
inline Eigen::Isometry3d makeRotationAbout(const Eigen::Vector3d& pivot_mm, const Eigen::Vector3d& axis,
                                           double angle_rad) {
  Eigen::Isometry3d x = Eigen::Isometry3d::Identity();
  x.linear() = Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
  x.translation() = pivot_mm - x.linear() * pivot_mm;
  return x;
}

}  // namespace rbfmuscle::test
