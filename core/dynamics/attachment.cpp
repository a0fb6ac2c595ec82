// SPDX-License-Identifier: Apache-2.0
#include "dynamics/attachment.h"

#include <algorithm>
#include <array>
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

/// The joint blend's ramp h(t) for t ≤ ½ (h(1 − t) = 1 − h(t)): quadratic on [0, e], linear after.
double calcRampToHalf(double t, double end_fraction) {
  const double slope = 1.0 / (1.0 - end_fraction);
  return t < end_fraction ? slope * t * t / (2.0 * end_fraction) : slope * (t - 0.5 * end_fraction);
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

namespace {

/// Unit directions from c to the attached centres of each of the two bones.
std::array<std::vector<Eigen::Vector3d>, 2> directionsOfAttached(const Eigen::Matrix3Xd& rest_centres_mm,
                                                                 const Attachments& attachments,
                                                                 const Eigen::Vector3d& c, const char* who) {
  if (attachments.num_bones != 2)
    throw std::invalid_argument(std::string(who) + ": needs 2 bones, got " + std::to_string(attachments.num_bones));
  if (static_cast<Eigen::Index>(attachments.bone_of_centre.size()) != rest_centres_mm.cols())
    throw std::invalid_argument(std::string(who) + ": attachments cover " +
                                std::to_string(attachments.bone_of_centre.size()) + " centres, " +
                                std::to_string(rest_centres_mm.cols()) + " given");
  if (!c.allFinite()) throw std::invalid_argument(std::string(who) + ": the joint centre is not finite");
  std::array<std::vector<Eigen::Vector3d>, 2> directions;
  for (Eigen::Index k = 0; k < rest_centres_mm.cols(); ++k) {
    const int b = attachments.bone_of_centre[static_cast<size_t>(k)];
    const Eigen::Vector3d d = rest_centres_mm.col(k) - c;
    if (b >= 0 && d.norm() > 0.0) directions[static_cast<size_t>(b)].push_back(d.normalized());
  }
  for (int b = 0; b < 2; ++b)
    if (directions[static_cast<size_t>(b)].empty())
      throw std::invalid_argument(std::string(who) + ": bone " + std::to_string(b) + " has no attached centre");
  return directions;
}

/// Angle (rad) between u and the nearest of `directions`.
double angleToNearest(const Eigen::Vector3d& u, const std::vector<Eigen::Vector3d>& directions) {
  double cosine = -1.0;
  for (const Eigen::Vector3d& d : directions) cosine = std::max(cosine, d.dot(u));
  return std::acos(std::clamp(cosine, -1.0, 1.0));
}

}  // namespace

Eigen::MatrixXd calcJointAngleBlendWeights(const Eigen::Matrix3Xd& points_mm, const Eigen::Matrix3Xd& rest_centres_mm,
                                           const Attachments& attachments, const Eigen::Vector3d& joint_centre_mm,
                                           double end_fraction) {
  const auto directions =
      directionsOfAttached(rest_centres_mm, attachments, joint_centre_mm, "calcJointAngleBlendWeights");
  if (!(end_fraction >= 0.0 && end_fraction < 0.5))
    throw std::invalid_argument("calcJointAngleBlendWeights: end fraction " + std::to_string(end_fraction) +
                                ", expected in [0, 0.5)");
  Eigen::MatrixXd weights(2, points_mm.cols());
#pragma omp parallel for schedule(static)
  for (Eigen::Index j = 0; j < points_mm.cols(); ++j) {
    const Eigen::Vector3d d = points_mm.col(j) - joint_centre_mm;
    double t = 0.5;  // at the centre itself, every direction is as near
    if (d.norm() > 0.0) {
      const double a0 = angleToNearest(d.normalized(), directions[0]);
      const double a1 = angleToNearest(d.normalized(), directions[1]);
      if (a0 + a1 > 0.0) t = a0 / (a0 + a1);
    }
    const double h = t <= 0.5 ? calcRampToHalf(t, end_fraction) : 1.0 - calcRampToHalf(1.0 - t, end_fraction);
    weights(0, j) = 1.0 - h;
    weights(1, j) = h;
  }
  return weights;
}

double calcAttachmentAngle(const Eigen::Matrix3Xd& rest_centres_mm, const Attachments& attachments,
                           const Eigen::Vector3d& joint_centre_mm) {
  const auto directions = directionsOfAttached(rest_centres_mm, attachments, joint_centre_mm, "calcAttachmentAngle");
  double angle = M_PI;
  for (const Eigen::Vector3d& u : directions[0]) angle = std::min(angle, angleToNearest(u, directions[1]));
  return angle;
}

double calcFoldFreeTurn(double attachment_angle_rad, double end_fraction) {
  return 4.0 * std::atan((1.0 - end_fraction) * attachment_angle_rad / 4.0);
}

double calcJointBlendEndWeight(double end_fraction) { return calcRampToHalf(end_fraction, end_fraction); }

}  // namespace rbfmuscle
