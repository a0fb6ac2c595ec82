// SPDX-License-Identifier: Apache-2.0
#include "pipeline/contact_stage.h"


namespace rbfmuscle {

ContactStage::ContactStage(BoneClearance clearance, const Eigen::AlignedBox3d& rest_box_M)
    : clearance_(std::move(clearance)), rest_box_M_(rest_box_M) {}

void ContactStage::run(MuscleState& state, const FrameInput& input) {
  Eigen::AlignedBox3d region;
  for (const Eigen::Isometry3d& motion : input.bone_motion_M)
    for (int c = 0; c < 8; ++c) region.extend(motion * rest_box_M_.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c)));
  clearance_.setPoses(input.X_MB, region);
  state.bones = &clearance_;
  report_ = Report{static_cast<double>(clearance_.countNearBones())};
}

}  // namespace rbfmuscle
