// SPDX-License-Identifier: Apache-2.0
#include "dynamics/attachment.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace rbfmuscle {

namespace {

void checkSize(const GaussianField& field, const Attachments& attachments, const char* who) {
  if (static_cast<int>(attachments.bone_of_centre.size()) != field.getNumCentres()) {
    throw std::invalid_argument(std::string(who) + ": attachments cover " +
                                std::to_string(attachments.bone_of_centre.size()) + " centres, the field has " +
                                std::to_string(field.getNumCentres()));
  }
}

}  // namespace

int Attachments::countAttached() const {
  int n = 0;
  for (int b : bone_of_centre) n += b >= 0 ? 1 : 0;
  return n;
}

int Attachments::countAttachedTo(int bone) const {
  int n = 0;
  for (int b : bone_of_centre) n += b == bone ? 1 : 0;
  return n;
}

Attachments makeFreeAttachments(int num_centres, int num_bones) {
  if (num_centres < 0 || num_bones < 0) {
    throw std::invalid_argument("makeFreeAttachments: negative count (centres " + std::to_string(num_centres) +
                                ", bones " + std::to_string(num_bones) + ")");
  }
  Attachments a;
  a.num_bones = num_bones;
  a.bone_of_centre.assign(static_cast<size_t>(num_centres), -1);
  return a;
}

void attachByLandmarks(const GaussianField& field, const std::vector<AttachmentLandmark>& landmarks,
                       Attachments& attachments) {
  checkSize(field, attachments, "attachByLandmarks");
  for (size_t i = 0; i < landmarks.size(); ++i) {
    const AttachmentLandmark& l = landmarks[i];
    if (l.bone < 0 || l.bone >= attachments.num_bones || !l.p_M_mm.allFinite() || !(l.radius_mm > 0.0) ||
        !std::isfinite(l.radius_mm)) {
      throw std::invalid_argument("attachByLandmarks: landmark " + std::to_string(i) + " has bone " +
                                  std::to_string(l.bone) + " (expected 0.." + std::to_string(attachments.num_bones - 1) +
                                  "), radius " + std::to_string(l.radius_mm) + " mm (expected > 0) or a non-finite point");
    }
  }
  const Eigen::Matrix3Xd& xi = field.getCentres();
  for (int k = 0; k < field.getNumCentres(); ++k) {
    if (attachments.isAttached(k)) continue;
    double best = std::numeric_limits<double>::infinity();
    int bone = -1;
    for (const AttachmentLandmark& l : landmarks) {
      const double d = (xi.col(k) - l.p_M_mm).norm();
      if (d <= l.radius_mm && d < best) {
        best = d;
        bone = l.bone;
      }
    }
    attachments.bone_of_centre[static_cast<size_t>(k)] = bone;
  }
}

Eigen::MatrixXd calcBlendWeights(const Eigen::Matrix3Xd& points_mm, const Eigen::Matrix3Xd& rest_centres_mm,
                                 const Attachments& attachments, double length_mm, double power) {
  if (static_cast<Eigen::Index>(attachments.bone_of_centre.size()) != rest_centres_mm.cols()) {
    throw std::invalid_argument("calcBlendWeights: attachments cover " + std::to_string(attachments.bone_of_centre.size()) +
                                " centres, " + std::to_string(rest_centres_mm.cols()) + " given");
  }
  if (!(length_mm > 0.0) || !std::isfinite(length_mm)) {
    throw std::invalid_argument("calcBlendWeights: blend length " + std::to_string(length_mm) + " mm, expected > 0");
  }
  if (attachments.countAttached() == 0) {
    throw std::invalid_argument("calcBlendWeights: no centre is attached to a bone");
  }
  if (!(power > 0.0) || !std::isfinite(power)) {
    throw std::invalid_argument("calcBlendWeights: power " + std::to_string(power) + ", expected > 0");
  }
  const int B = attachments.num_bones;
  const Eigen::Index M = points_mm.cols();
  Eigen::MatrixXd weights = Eigen::MatrixXd::Zero(B, M);
  const double inf = std::numeric_limits<double>::infinity();
#pragma omp parallel for schedule(static)
  for (Eigen::Index j = 0; j < M; ++j) {
    Eigen::VectorXd d = Eigen::VectorXd::Constant(B, inf);
    for (Eigen::Index k = 0; k < rest_centres_mm.cols(); ++k) {
      const int b = attachments.bone_of_centre[static_cast<size_t>(k)];
      if (b < 0) continue;
      const double dist = (points_mm.col(j) - rest_centres_mm.col(k)).norm();
      if (dist < d(b)) d(b) = dist;
    }
    double sum = 0.0;
    for (int b = 0; b < B; ++b) {
      const double w = std::isfinite(d(b)) ? (power == 1.0 ? 1.0 / (d(b) + length_mm) : std::pow(d(b) + length_mm, -power)) : 0.0;
      weights(b, j) = w;
      sum += w;
    }
    weights.col(j) /= sum;
  }
  return weights;
}

}  // namespace rbfmuscle
