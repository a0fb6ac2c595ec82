#include "dynamics/motion_prediction.h"

#include <stdexcept>
#include <string>

namespace rbfmuscle {

namespace {

Eigen::Quaterniond add(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b, double s) {
  return Eigen::Quaterniond(a.w() + s * b.w(), a.x() + s * b.x(), a.y() + s * b.y(), a.z() + s * b.z());
}

void checkTransforms(const Eigen::MatrixXd& weights, const std::vector<DualQuaternion>& transforms, const char* who) {
  if (weights.rows() != static_cast<Eigen::Index>(transforms.size())) {
    throw std::invalid_argument(std::string(who) + ": " + std::to_string(weights.rows()) + " weight rows for " +
                                std::to_string(transforms.size()) + " bone transforms");
  }
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

Eigen::Isometry3d blendTransforms(const Eigen::Ref<const Eigen::VectorXd>& weights,
                                  const std::vector<DualQuaternion>& transforms) {
  if (weights.size() != static_cast<Eigen::Index>(transforms.size()) || transforms.empty()) {
    throw std::invalid_argument("blendTransforms: " + std::to_string(weights.size()) + " weights for " +
                                std::to_string(transforms.size()) + " transforms");
  }
  if (!(weights.sum() > 0.0) || (weights.array() < 0.0).any()) {
    throw std::invalid_argument("blendTransforms: weights must be >= 0 with a positive sum");
  }
  const Eigen::VectorXd w = weights;
  Eigen::Isometry3d x = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d origin = applyBlend(w.data(), transforms, Eigen::Vector3d::Zero());
  for (int i = 0; i < 3; ++i) {
    x.linear().col(i) = applyBlend(w.data(), transforms, Eigen::Vector3d::Unit(i)) - origin;
  }
  x.translation() = origin;
  return x;
}

void predictPoints(const Eigen::Matrix3Xd& rest_points_mm, const Eigen::MatrixXd& weights,
                   const std::vector<DualQuaternion>& transforms, Eigen::Matrix3Xd& out) {
  checkTransforms(weights, transforms, "predictPoints");
  if (weights.cols() != rest_points_mm.cols()) {
    throw std::invalid_argument("predictPoints: " + std::to_string(weights.cols()) + " weight columns for " +
                                std::to_string(rest_points_mm.cols()) + " points");
  }
  out.resize(3, rest_points_mm.cols());
#pragma omp parallel for schedule(static)
  for (Eigen::Index j = 0; j < rest_points_mm.cols(); ++j) {
    out.col(j) = applyBlend(weights.col(j).data(), transforms, rest_points_mm.col(j));
  }
}

void predictCentres(const Eigen::Matrix3Xd& rest_centres_mm, const Attachments& attachments,
                    const Eigen::MatrixXd& centre_weights, const std::vector<DualQuaternion>& transforms,
                    Eigen::Matrix3Xd& out) {
  checkTransforms(centre_weights, transforms, "predictCentres");
  if (centre_weights.cols() != rest_centres_mm.cols() ||
      static_cast<Eigen::Index>(attachments.bone_of_centre.size()) != rest_centres_mm.cols()) {
    throw std::invalid_argument("predictCentres: sizes differ (centres " + std::to_string(rest_centres_mm.cols()) +
                                ", weight columns " + std::to_string(centre_weights.cols()) + ", attachments " +
                                std::to_string(attachments.bone_of_centre.size()) + ")");
  }
  out.resize(3, rest_centres_mm.cols());
  for (Eigen::Index k = 0; k < rest_centres_mm.cols(); ++k) {
    const int b = attachments.bone_of_centre[static_cast<size_t>(k)];
    if (b >= 0) {
      const DualQuaternion& dq = transforms[static_cast<size_t>(b)];
      out.col(k) = dq.real * Eigen::Vector3d(rest_centres_mm.col(k)) + 2.0 * (dq.dual * dq.real.conjugate()).vec();
    } else {
      out.col(k) = applyBlend(centre_weights.col(k).data(), transforms, rest_centres_mm.col(k));
    }
  }
}

}  // namespace rbfmuscle
