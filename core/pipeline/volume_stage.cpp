// SPDX-License-Identifier: Apache-2.0
#include "pipeline/volume_stage.h"


namespace rbfmuscle {

namespace {

/// The folds to a point outside a bone but near it (tissue_fold.h).
FoldFinder findFolds(const MuscleState& state) {
  if (!state.bones) return nullptr;
  const BoneClearance& bones = *state.bones;
  return [&bones](const Eigen::Vector3d& y, double floor,
                  const std::function<void(const Eigen::Vector3d&, const Eigen::Vector3d&, double)>& visit) {
    bones.visitFolds(y, floor, [&](const Eigen::Vector3d& mirror, const Eigen::Vector3d& foot, const Eigen::Vector3d&,
                            double cap_mm, const Eigen::Vector3d&) { visit(mirror, foot, cap_mm); });
  };
}

}  // namespace

VolumeStage::VolumeStage(const MuscleState& rest_state, NeighbourLists quadrature_lists,
                         const std::vector<bool>& free_mask, double cell_volume_mm3, double cell_mm,
                         const BalanceSettings& settings)
    : lists_(std::move(quadrature_lists)),
      balance_(rest_state.field.getWeights(), free_mask, cell_volume_mm3, cell_mm, settings) {
  balance_.setRest(rest_state.field, rest_state.quadrature_mm, lists_, rest_state.clearance_mm, findFolds(rest_state));
}

void VolumeStage::run(MuscleState& state, const FrameInput&) {
  const BalanceReport r = balance_.balance(state.field, state.quadrature_mm, lists_, state.volume_changes,
                                          state.clearance_mm, findFolds(state));
  report_ = Report{r.volume_mm3, r.ratio, r.ratio_before, r.correction, static_cast<double>(static_cast<int>(r.stop))};
}

}  // namespace rbfmuscle
