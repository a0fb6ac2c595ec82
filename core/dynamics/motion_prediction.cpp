// SPDX-License-Identifier: Apache-2.0
#include "dynamics/motion_prediction.h"


namespace rbfmuscle {

namespace {

Eigen::Quaterniond add(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b, double s) {
  return Eigen::Quaterniond(a.w() + s * b.w(), a.x() + s * b.x(), a.y() + s * b.y(), a.z() + s * b.z());
}

}  // namespace

Eigen::Vector3d applyBlend(const double* w, const std::vector<DualQuaternion>& dqs, const Eigen::Vector3d& p) {
  const int B = static_cast<int>(dqs.size());
  int pivot = 0;
  for (int b = 1; b < B; ++b) if (w[b] > w[pivot]) pivot = b;
  Eigen::Quaterniond real(0, 0, 0, 0), dual(0, 0, 0, 0);
  for (int b = 0; b < B; ++b) {
    if (w[b] == 0.0) continue;
    const double sign = dqs[b].real.coeffs().dot(dqs[pivot].real.coeffs()) < 0.0 ? -1.0 : 1.0;
    real = add(real, dqs[b].real, sign * w[b]);
    dual = add(dual, dqs[b].dual, sign * w[b]);
  }
  const double n = real.norm();
  real.coeffs() /= n;
  dual.coeffs() /= n;
  // t = 2 (dual ⊗ real*) − the part of dual along real is removed by the vector extraction.
  const Eigen::Quaterniond t = dual * real.conjugate();
  const Eigen::Vector3d translation = 2.0 * t.vec();
  return real * p + translation;
}

Eigen::Vector3d applyLinearBlend(const double* w, const std::vector<Eigen::Isometry3d>& motions,
                                 const Eigen::Vector3d& p) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double weight = 0.0;
  for (size_t b = 0; b < motions.size(); ++b) {
    if (w[b] == 0.0) continue;
    sum += w[b] * (motions[b] * p);
    weight += w[b];
  }
  return sum / weight;
}

DualQuaternion toDualQuaternion(const Eigen::Isometry3d& transform) {
  DualQuaternion dq;
  dq.real = Eigen::Quaterniond(transform.rotation()).normalized();
  const Eigen::Vector3d t = transform.translation();
  const Eigen::Quaterniond tq(0.0, t.x(), t.y(), t.z());
  dq.dual = tq * dq.real;
  dq.dual.coeffs() *= 0.5;
  return dq;
}

Eigen::Isometry3d toIsometry(const DualQuaternion& dq) {
  Eigen::Isometry3d x = Eigen::Isometry3d::Identity();
  x.linear() = dq.real.normalized().toRotationMatrix();
  x.translation() = 2.0 * (dq.dual * dq.real.conjugate()).vec();
  return x;
}

}  // namespace rbfmuscle
