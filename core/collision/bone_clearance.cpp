// SPDX-License-Identifier: Apache-2.0
#include "collision/bone_clearance.h"

#include "geometry/mesh_distance.h"

#include <algorithm>
#include <stdexcept>

namespace rbfmuscle {

BoneClearance::BoneClearance(std::vector<ClearanceBone> bones) : bones_(std::move(bones)) {
  for (const ClearanceBone& bone : bones_) {
    if (!bone.grid) throw std::invalid_argument("BoneClearance: bone '" + bone.name + "' has no distance grid");
    far_value_mm_ = std::max(far_value_mm_, bone.grid->getSettings().band_mm);
  }
  X_MB_.assign(bones_.size(), Eigen::Isometry3d::Identity());
  X_BM_ = X_MB_;
}

void BoneClearance::setPoses(const std::vector<Eigen::Isometry3d>& X_MB, const Eigen::AlignedBox3d& region_M) {
  if (X_MB.size() != bones_.size())
    throw std::invalid_argument("BoneClearance: " + std::to_string(X_MB.size()) + " poses for " +
                                std::to_string(bones_.size()) + " bones");
  near_.clear();
  for (size_t b = 0; b < bones_.size(); ++b) {
    if (!X_MB[b].matrix().allFinite()) throw std::invalid_argument("BoneClearance: pose of '" + bones_[b].name + "' is not finite");
    X_MB_[b] = X_MB[b];
    X_BM_[b] = X_MB[b].inverse(Eigen::Isometry);
    // The posed grid box's bounding box in M: its 8 corners moved.
    const Eigen::AlignedBox3d box_B = bones_[b].grid->getGridBox();
    Eigen::AlignedBox3d box_M;
    for (int c = 0; c < 8; ++c) box_M.extend(X_MB[b] * box_B.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c)));
    if (!region_M.isEmpty() && box_M.intersects(region_M)) near_.push_back(static_cast<int>(b));
  }
}

ClearanceSample BoneClearance::sampleBone(int b, const Eigen::Vector3d& y_M) const {
  const BoneDistanceGrid& grid = *bones_[static_cast<size_t>(b)].grid;
  const Eigen::Vector3d p_B = X_BM_[static_cast<size_t>(b)] * y_M;
  BoneDistanceSample s = grid.sample(p_B);
  if (!s.near && s.value_mm < 0.0) {  // deeper inside than the band: the exact distance, so the way out is known
    const SignedClosestPoint q = grid.getMeshDistance().findSignedClosestPoint(p_B);
    const Eigen::Vector3d away = p_B - q.point_mm;
    s.value_mm = q.signed_distance_mm;
    s.gradient_B = away.norm() > 0.0 ? Eigen::Vector3d((q.signed_distance_mm < 0.0 ? -1.0 : 1.0) * away.normalized())
                                     : Eigen::Vector3d::Zero();
    s.near = true;
  }
  ClearanceSample out;
  out.value_mm = s.value_mm;
  out.near = s.near;
  out.gradient = s.near ? Eigen::Vector3d(X_MB_[static_cast<size_t>(b)].linear() * s.gradient_B) : Eigen::Vector3d::Zero();
  return out;
}

ClearanceSample BoneClearance::sample(const Eigen::Vector3d& y_M) const {
  ClearanceSample best;
  best.value_mm = far_value_mm_;
  for (int b : near_) {
    const ClearanceSample s = sampleBone(b, y_M);
    if (s.value_mm < best.value_mm) best = s;
  }
  return best;
}

}  // namespace rbfmuscle
