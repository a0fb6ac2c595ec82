#include "fibres/fibre_tracker.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace rbfmuscle {

FibreTracker::FibreTracker(const RestFibres& rest, const Eigen::Matrix3Xd& rest_centres_mm,
                           const Attachments& attachments, int origin_bone, int insertion_bone,
                           double blend_length_mm, const ProjectionSettings& projection)
    : rest_(rest), projection_(projection) {
  checkProjectionSettings(projection);
  const int bones = attachments.num_bones;
  for (int bone : {origin_bone, insertion_bone})
    if (bone < 0 || bone >= bones)
      throw std::invalid_argument("FibreTracker: bone " + std::to_string(bone) + " outside [0, " +
                                  std::to_string(bones) + ")");
  const int per = rest.segments + 1;
  if (rest.count < 1 || rest.segments < 1 || rest.points_mm.cols() != static_cast<Eigen::Index>(rest.count) * per)
    throw std::invalid_argument("FibreTracker: rest fibres hold " + std::to_string(rest.points_mm.cols()) +
                                " points for " + std::to_string(rest.count) + " fibres of " +
                                std::to_string(rest.segments) + " segments");
  weights_ = calcBlendWeights(rest.points_mm, rest_centres_mm, attachments, blend_length_mm);
  for (int i = 0; i < rest.count; ++i) {
    weights_.col(static_cast<Eigen::Index>(i) * per).setZero();
    weights_(origin_bone, static_cast<Eigen::Index>(i) * per) = 1.0;
    weights_.col(static_cast<Eigen::Index>(i) * per + rest.segments).setZero();
    weights_(insertion_bone, static_cast<Eigen::Index>(i) * per + rest.segments) = 1.0;
  }
  calcFibreLengths(rest.points_mm, rest.segments, rest_.lengths_mm);
  rest_mean_mm_ = rest_.lengths_mm.mean();
  transforms_.resize(static_cast<size_t>(bones));
}

const FibreFrame& FibreTracker::update(const GaussianField& field_M,
                                       const std::vector<Eigen::Isometry3d>& bone_motion_M) {
  if (bone_motion_M.size() != transforms_.size())
    throw std::invalid_argument("FibreTracker::update: " + std::to_string(bone_motion_M.size()) +
                                " bone transforms for " + std::to_string(transforms_.size()) + " bones");
  for (size_t b = 0; b < transforms_.size(); ++b) transforms_[b] = toDualQuaternion(bone_motion_M[b]);
  predictPoints(rest_.points_mm, weights_, transforms_, frame_.points_mm);
  const int per = rest_.segments + 1;
  const int segments = rest_.segments;
  frame_.projected = 0;
  frame_.placed = 0;
  frame_.outside = 0;
  frame_.end_offset_max_mm = 0;
  values_.resize(frame_.points_mm.cols());
  // 1. Monotone ascent of f for every point below the margin; ends move at most end_max_move_mm.
  for (Eigen::Index c = 0; c < frame_.points_mm.cols(); ++c) {
    const int j = static_cast<int>(c % per);
    const bool end = j == 0 || j == segments;
    Eigen::Vector3d p = frame_.points_mm.col(c);
    const ProjectionResult r = end ? projectInside(field_M, projection_, p, projection_.end_max_move_mm)
                                   : projectInside(field_M, projection_, p);
    if (r.steps > 0) {
      if (end) frame_.end_offset_max_mm = std::max(frame_.end_offset_max_mm, (p - frame_.points_mm.col(c)).norm());
      frame_.points_mm.col(c) = p;
      ++frame_.projected;
    }
    values_(c) = r.value;
  }
  // 2. Interior points still outside: placed from the nearest inside points of their fibre.
  for (Eigen::Index first = 0; first < frame_.points_mm.cols(); first += per)
    for (int j = 1; j < segments; ++j) {
      if (values_(first + j) > 0) continue;
      int a = j - 1, b = j + 1;
      while (a >= 0 && !(values_(first + a) > 0)) --a;
      while (b <= segments && !(values_(first + b) > 0)) ++b;
      if (a < 0 || b > segments) continue;
      Eigen::Vector3d p = frame_.points_mm.col(first + j);
      values_(first + j) =
          placeBetweenInsideNeighbours(field_M, projection_, frame_.points_mm.col(first + a),
                                       frame_.points_mm.col(first + b), static_cast<double>(j - a) / (b - a), p);
      frame_.points_mm.col(first + j) = p;
      ++frame_.placed;
    }
  frame_.outside = static_cast<int>((values_.array() <= 0).count());
  calcFibreLengths(frame_.points_mm, rest_.segments, frame_.lengths_mm);
  frame_.mean_mm = frame_.lengths_mm.mean();
  frame_.min_mm = frame_.lengths_mm.minCoeff();
  frame_.max_mm = frame_.lengths_mm.maxCoeff();
  frame_.normalised_mean = frame_.mean_mm / rest_mean_mm_;
  return frame_;
}

}  // namespace rbfmuscle
