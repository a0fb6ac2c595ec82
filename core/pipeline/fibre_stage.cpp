// SPDX-License-Identifier: Apache-2.0
#include "pipeline/fibre_stage.h"

#include "dynamics/joint_lift_off.h"
#include "fibres/fibre_projection.h"
#include "rbf/parallel_blocks.h"

#include <algorithm>

namespace rbfmuscle {

FibreStage::FibreStage(std::shared_ptr<TissueLattice> lattice, RestFibres rest, const DeformedField& rest_field,
                       const ProjectionSettings& projection)
    : lattice_(std::move(lattice)), rest_(std::move(rest)), projection_(projection) {
  checkProjectionSettings(projection);
  const int per = rest_.segments + 1;
  std::vector<int> tied(static_cast<size_t>(rest_.points_mm.cols()), -1);
  for (int i = 0; i < rest_.count; ++i) {
    tied[static_cast<size_t>(i * per)] = 0;
    tied[static_cast<size_t>(i * per + rest_.segments)] = 1;
  }
  binding_ = lattice_->bind(rest_.points_mm, tied);
  std::vector<int> attached_to(static_cast<size_t>(rest_.attachments_mm.cols()));
  for (size_t a = 0; a < attached_to.size(); ++a) attached_to[a] = static_cast<int>(a % 2);
  attachment_binding_ = lattice_->bind(rest_.attachments_mm, attached_to);
  lists_ = findMaterialNeighbours(rest_field, rest_.points_mm);
  calcFibreLengths(rest_.points_mm, rest_.segments, rest_.attachments_mm, rest_.lengths_mm);
  rest_mean_mm_ = rest_.lengths_mm.mean();
  lengths_mm_ = rest_.lengths_mm;
}

void FibreStage::run(MuscleState& state, const FrameInput& input) {
  Eigen::Matrix3Xd& points = state.fibre_points_mm;
  lattice_->carry(binding_, points);
  lattice_->carry(attachment_binding_, state.fibre_attachments_mm);
  const int per = rest_.segments + 1, segments = rest_.segments;
  // 0. A taut muscle's interior fibre points move towards the taut map's chords, as far as the
  // muscle allows. The whole field: a point can end several mm from its rest kernels.
  const double taut_fraction = lattice_->getTautFraction();
  const long count = static_cast<long>(points.cols());
  double taut_move = 0.0;
  if (taut_fraction > 0.0) {
    lattice_->carryTaut(binding_, taut_mm_);
    taut_move = advanceInteriorPoints(MuscleShape(state, nullptr, 0, BoneContact::kCut), taut_mm_, points);
  }
  values_.resize(count);
  // 1. Monotone ascent of min(f, s) for every point below the margin; ends move at most end_max_move_mm.
  moves_mm_.setZero(count);
  steps_.setZero(count);
  forEachBlock(count, kBlock, [&](long begin, long end) {
    for (long c = begin; c < end; ++c) {
      const int j = static_cast<int>(c % per);
      const bool is_end = j == 0 || j == segments;
      const MuscleShape shape(state, lists_.begin(static_cast<int>(c)), lists_.count(static_cast<int>(c)),
                              BoneContact::kCut);
      Eigen::Vector3d p = points.col(c);
      const ProjectionResult r = is_end ? projectInside(shape, projection_, p, projection_.end_max_move_mm)
                                        : projectInside(shape, projection_, p);
      if (r.steps > 0) {
        if (is_end) moves_mm_[c] = (p - points.col(c)).norm();
        points.col(c) = p;
      }
      steps_[c] = r.steps;
      values_[c] = r.value;
    }
  });
  const int projected = static_cast<int>((steps_.array() > 0).count());
  const double end_offset = count > 0 ? moves_mm_.maxCoeff() : 0.0;
  // 2. Interior points still outside: they climb on by a pattern search, else are placed from
  // the nearest inside points of their fibre. The whole field, not a point's rest kernel list:
  // the list reaches about one kernel radius from the point's rest place, and the neighbours
  // are up to a segment away (19 mm on the psoas), where the list can miss the kernels that
  // hold them inside. Rare, so cheap.
  const MuscleShape whole(state, nullptr, 0, BoneContact::kCut);
  for (Eigen::Index first = 0; first < points.cols(); first += per)
    for (int j = 1; j < segments; ++j) {
      if (values_[first + j] > 0) continue;
      Eigen::Vector3d p = points.col(first + j);
      values_[first + j] = climbByPatternSearch(whole, projection_, p);
      points.col(first + j) = p;
    }
  for (Eigen::Index first = 0; first < points.cols(); first += per)
    for (int j = 1; j < segments; ++j) {
      if (values_[first + j] > 0) continue;
      int a = j - 1, b = j + 1;
      while (a >= 0 && !(values_[first + a] > 0)) --a;
      while (b <= segments && !(values_[first + b] > 0)) ++b;
      if (a < 0 || b > segments) continue;
      const int c = static_cast<int>(first + j);
      if (!(whole.calcValue(points.col(first + a)) > 0.0) || !(whole.calcValue(points.col(first + b)) > 0.0)) continue;
      Eigen::Vector3d p = points.col(c);
      values_[c] = placeBetweenInsideNeighbours(whole, projection_, points.col(first + a), points.col(first + b),
                                                static_cast<double>(j - a) / (b - a), p);
      points.col(c) = p;
    }
  // 3. A shortened muscle's fibres lift off the joint towards their strings, within the muscle.
  const double lift_move = liftOff(state, input, whole);
  calcFibreLengths(points, segments, state.fibre_attachments_mm, lengths_mm_);
  const double mean = lengths_mm_.mean();
  report_ = Report{mean, lengths_mm_.minCoeff(), lengths_mm_.maxCoeff(), mean / rest_mean_mm_,
                   static_cast<double>(projected), static_cast<double>((values_.array() <= 0.0).count()), end_offset,
                   taut_fraction, taut_move, lift_move};
}

double FibreStage::liftOff(MuscleState& state, const FrameInput& input, const ImplicitField& muscle) {
  const double fraction = lattice_->getLiftFraction();
  const std::optional<JointTurn> turn = lattice_->getJointTurn();
  if (!(fraction > 0.0) || !turn) return 0.0;
  Eigen::Matrix3Xd& points = state.fibre_points_mm;
  const int per = rest_.segments + 1;
  const Eigen::Matrix3Xd rest = input.bone_motion_M[0] * rest_.points_mm;  // the rest fibres, seen from the origin bone
  Eigen::Matrix3Xd rises(3, points.cols());
  for (Eigen::Index first = 0; first < points.cols(); first += per)
    rises.middleCols(first, per) = calcSagRisesSinceRest(points.middleCols(first, per), rest.middleCols(first, per),
                                                         turn->centre_mm, turn->axis, lattice_->getCellSize());
  const Eigen::Matrix3Xd targets = points + fraction * lattice_->spreadLikeRises(binding_, rises);
  return advanceInteriorPoints(muscle, targets, points);
}

double FibreStage::advanceInteriorPoints(const ImplicitField& muscle, const Eigen::Matrix3Xd& targets_mm,
                                         Eigen::Matrix3Xd& points) {
  const int per = rest_.segments + 1;
  const long count = static_cast<long>(points.cols());
  moves_mm_.setZero(count);
  forEachBlock(count, kBlock, [&](long begin, long end) {
    for (long c = begin; c < end; ++c) {
      const int j = static_cast<int>(c % per);
      if (j == 0 || j == rest_.segments) continue;
      const Eigen::Vector3d p = advanceInside(muscle, projection_, points.col(c), targets_mm.col(c));
      moves_mm_[c] = (p - points.col(c)).norm();
      points.col(c) = p;
    }
  });
  return count > 0 ? moves_mm_.maxCoeff() : 0.0;
}

}  // namespace rbfmuscle
