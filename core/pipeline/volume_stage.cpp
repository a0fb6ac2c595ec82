// SPDX-License-Identifier: Apache-2.0
#include "pipeline/volume_stage.h"

namespace rbfmuscle {

VolumeStage::VolumeStage(const MuscleState& rest_state, NeighbourLists quadrature_lists,
                         const std::vector<bool>& free_mask, double cell_volume_mm3, double cell_mm,
                         const BalanceSettings& settings)
    : lists_(std::move(quadrature_lists)),
      balance_(rest_state.field.getWeights(), free_mask, cell_volume_mm3, cell_mm, settings) {
  balance_.setRest(rest_state.field, rest_state.quadrature_mm, lists_, rest_state.clearance_mm);
}

void VolumeStage::run(MuscleState& state, const FrameInput&) {
  const BalanceReport r = balance_.balance(state.field, state.quadrature_mm, lists_, state.volume_changes, state.clearance_mm);
  report_ = Report{r.volume_mm3, r.ratio, r.ratio_before, r.correction, static_cast<double>(static_cast<int>(r.stop))};
}

}  // namespace rbfmuscle
