// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// A small rod-shaped muscle for the fibre tests, its attachments and bends.
#include "dynamics/attachment.h"
#include "fibres/fibre_generator.h"
#include "rbf/gaussian_field.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <vector>

namespace rbfmuscle::test {

/// A rod along x from about −40 to +40 mm, about 20 mm thick: five rows (y, z) ∈
/// {(0,0), (±4,0), (0,±4)} of 13 Gaussians at x = −30 … 30 (spacing 5 mm), α = 0.02 mm⁻²,
/// λ = 2.5 (±10 % deterministic variation), b = −5 (the fit convention).
inline GaussianField makeFibreRod() {
  const int per_row = 13;
  const Eigen::Vector2d rows[] = {{0, 0}, {4, 0}, {-4, 0}, {0, 4}, {0, -4}};
  Eigen::Matrix3Xd xi(3, 5 * per_row);
  Eigen::VectorXd lambda(5 * per_row), alpha(5 * per_row);
  int k = 0;
  for (const Eigen::Vector2d& row : rows)
    for (int i = 0; i < per_row; ++i, ++k) {
      xi.col(k) = Eigen::Vector3d(-30.0 + 5.0 * i, row.x(), row.y());
      lambda(k) = 2.5 * (1.0 + 0.1 * std::sin(1.7 * k));
      alpha(k) = 0.02;
    }
  return GaussianField(-5.0, xi, lambda, alpha);
}

/// Origin landmark (bone 0) and insertion landmark (bone 1) at the rod's ends (mm).
inline Eigen::Matrix3Xd rodOrigin() { return Eigen::Vector3d(-32, 0, 0); }
inline Eigen::Matrix3Xd rodInsertion() { return Eigen::Vector3d(32, 0, 0); }

/// Centres within 9 mm of an end landmark attach to its bone.
inline Attachments makeFibreRodAttachments(const GaussianField& field) {
  Attachments a = makeFreeAttachments(field.getNumCentres(), 2);
  attachByLandmarks(field,
                    {AttachmentLandmark{0, rodOrigin().col(0), 9.0}, AttachmentLandmark{1, rodInsertion().col(0), 9.0}},
                    a);
  return a;
}

/// Small fast settings: 30 fibres of 10 segments on a 6000-node grid.
inline FibreSettings makeSmallFibreSettings() {
  FibreSettings s;
  s.count = 30;
  s.segments = 10;
  s.grid_nodes = 6000;
  s.attachment_radius_mm = 6;
  return s;
}

/// Rotation by `angle_rad` about the axis through `pivot_mm` along `axis`.
inline Eigen::Isometry3d makeTurn(const Eigen::Vector3d& pivot_mm, const Eigen::Vector3d& axis, double angle_rad) {
  Eigen::Isometry3d x = Eigen::Isometry3d::Identity();
  x.linear() = Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
  x.translation() = pivot_mm - x.linear() * pivot_mm;
  return x;
}

}  // namespace rbfmuscle::test
