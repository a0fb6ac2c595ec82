#include "fibres/fibre_tracker.h"

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
  frame_.projected = 0;
  frame_.outside = 0;
  for (Eigen::Index c = 0; c < frame_.points_mm.cols(); ++c) {
    const int j = static_cast<int>(c % per);
    if (j != 0 && j != rest_.segments) {
      Eigen::Vector3d p = frame_.points_mm.col(c);
      if (projectInside(field_M, projection_, p) > 0) {
        frame_.points_mm.col(c) = p;
        ++frame_.projected;
      }
    }
    frame_.outside += field_M.calcValue(frame_.points_mm.col(c)) <= 0;
  }
  calcFibreLengths(frame_.points_mm, rest_.segments, frame_.lengths_mm);
  frame_.mean_mm = frame_.lengths_mm.mean();
  frame_.min_mm = frame_.lengths_mm.minCoeff();
  frame_.max_mm = frame_.lengths_mm.maxCoeff();
  frame_.normalised_mean = frame_.mean_mm / rest_mean_mm_;
  return frame_;
}

}  // namespace rbfmuscle
