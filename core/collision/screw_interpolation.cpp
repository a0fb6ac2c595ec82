#include "collision/screw_interpolation.h"

#include <cmath>

namespace rbfmuscle {

Eigen::Isometry3d interpolateScrew(const Eigen::Isometry3d& X_a, const Eigen::Isometry3d& X_b, double s) {
  const Eigen::Isometry3d D = X_b * X_a.inverse();
  const Eigen::AngleAxisd rotation(D.linear());
  const double theta = rotation.angle();
  Eigen::Isometry3d D_s = Eigen::Isometry3d::Identity();
  if (theta < 1e-12) {
    D_s.translation() = s * D.translation();
    return D_s * X_a;
  }
  const Eigen::Vector3d u = rotation.axis();
  const Eigen::Vector3d t = D.translation();
  const Eigen::Vector3d slide = u.dot(t) * u;
  // (I − R) c = t − slide for the axis point c ⊥ u; (I − R) + u uᵀ is invertible for θ ≠ 0.
  const Eigen::Matrix3d A = Eigen::Matrix3d::Identity() - D.linear() + u * u.transpose();
  const Eigen::Vector3d c = A.partialPivLu().solve(t - slide);
  D_s.linear() = Eigen::AngleAxisd(s * theta, u).toRotationMatrix();
  D_s.translation() = c - D_s.linear() * c + s * slide;
  return D_s * X_a;
}

}  // namespace rbfmuscle
