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

/// The rod's two ends (x = −30 … −15 and 15 … 30) joined by a neck of one row of narrow
/// Gaussians (x = −14 … 14 at y = z = 0.5, 1 mm apart, α = 1 mm⁻², λ = neck_weight; none at
/// 0): with λ = 4.45 the neck's inside {f ≥ 0.5} is about 1.3 mm across, and it runs between
/// the nodes of a 6000-node interior grid (1.24 mm apart), which splits it.
inline GaussianField makeFibreDumbbell(double neck_weight) {
  const Eigen::Vector2d rows[] = {{0, 0}, {4, 0}, {-4, 0}, {0, 4}, {0, -4}};
  std::vector<Eigen::Vector3d> xi;
  std::vector<double> lambda, alpha;
  for (const Eigen::Vector2d& row : rows)
    for (double x : {-30.0, -25.0, -20.0, -15.0, 15.0, 20.0, 25.0, 30.0}) {
      xi.emplace_back(x, row.x(), row.y());
      lambda.push_back(2.5);
      alpha.push_back(0.02);
    }
  if (neck_weight > 0.0)
    for (int x = -14; x <= 14; ++x) {
      xi.emplace_back(x, 0.5, 0.5);
      lambda.push_back(neck_weight);
      alpha.push_back(1.0);
    }
  Eigen::Matrix3Xd centres(3, static_cast<Eigen::Index>(xi.size()));
  for (size_t k = 0; k < xi.size(); ++k) centres.col(static_cast<Eigen::Index>(k)) = xi[k];
  return GaussianField(-5.0, centres, Eigen::Map<Eigen::VectorXd>(lambda.data(), static_cast<Eigen::Index>(lambda.size())),
                       Eigen::Map<Eigen::VectorXd>(alpha.data(), static_cast<Eigen::Index>(alpha.size())));
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
