// SPDX-License-Identifier: Apache-2.0
#include "model/joint_centre.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace rbfmuscle {

std::optional<JointCentre> findJointCentre(const Skeleton& skeleton, int body_a, int body_b,
                                           const Eigen::Vector3d& near_G_mm) {
  const int bodies = static_cast<int>(skeleton.getBodyNames().size());
  if (body_a < 0 || body_a >= bodies || body_b < 0 || body_b >= bodies)
    throw std::invalid_argument("findJointCentre: body " + std::to_string(body_a) + " or " + std::to_string(body_b) +
                                " out of range 0.." + std::to_string(bodies - 1));
  Skeleton probe = Skeleton::fromFile(skeleton.getModelPath());
  const Eigen::VectorXd rest = skeleton.getRestCoordinateValues();
  probe.setCoordinateValues(rest);
  const Eigen::Isometry3d X_GA = probe.getBodyTransform(body_a);
  const Eigen::Isometry3d X_AB_rest = X_GA.inverse() * probe.getBodyTransform(body_b);
  constexpr double kStep_rad = 0.1;  // large enough that (R − I) is well above rounding, small for any range
  std::vector<Eigen::Isometry3d> moves;  // B relative to A, rest → probe, in A
  int turning = 0;
  for (size_t c = 0; c < skeleton.getCoordinates().size(); ++c) {
    if (skeleton.getCoordinates()[c].motion != CoordinateMotion::kRotational) continue;
    bool turns = false;
    for (double side : {1.0, -1.0}) {
      Eigen::VectorXd q = rest;
      q[static_cast<Eigen::Index>(c)] += side * kStep_rad;
      probe.setCoordinateValues(q);
      const Eigen::Isometry3d X_AB = probe.getBodyTransform(body_a).inverse() * probe.getBodyTransform(body_b);
      const Eigen::Isometry3d move = X_AB * X_AB_rest.inverse();
      if (Eigen::AngleAxisd(move.linear()).angle() < 1e-9) continue;  // this coordinate does not turn B about A
      moves.push_back(move);
      turns = true;
    }
    turning += turns ? 1 : 0;
  }
  if (moves.empty()) return std::nullopt;
  // Normal equations of Σ|(R − I)c + t|², with a weak pull (1e-9 of the curvature) to `near`
  // that only decides along a hinge's axis, where the sum is flat.
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (const Eigen::Isometry3d& m : moves) {
    const Eigen::Matrix3d a = m.linear() - Eigen::Matrix3d::Identity();
    normal += a.transpose() * a;
    rhs -= a.transpose() * m.translation();
  }
  const double pull = 1e-9 * std::max(normal.trace(), 1e-300);
  const Eigen::Vector3d near_A = X_GA.inverse() * near_G_mm;
  const Eigen::Vector3d c_A = (normal + pull * Eigen::Matrix3d::Identity()).ldlt().solve(rhs + pull * near_A);
  JointCentre centre;
  centre.p_G_mm = X_GA * c_A;
  centre.coordinates = turning;
  for (const Eigen::Isometry3d& m : moves) centre.residual_mm = std::max(centre.residual_mm, (m * c_A - c_A).norm());
  return centre;
}

}  // namespace rbfmuscle
