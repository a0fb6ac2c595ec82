// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Stage 4: the volume held at its rest value by one scalar.
#include "dynamics/volume_balance.h"
#include "pipeline/frame_stage.h"

namespace rbfmuscle {

/// Measures the muscle's volume outside the bones, with what they took folded out of them
/// (tissue_fold.h), over the carried quadrature and corrects
/// the free kernels' weights (volume_balance.h).
class VolumeStage final : public FrameStage {
 public:
  /// @param rest_state a state holding the rest field, rest quadrature and rest clearance
  /// @param quadrature_lists the quadrature points' rest kernel lists
  VolumeStage(const MuscleState& rest_state, NeighbourLists quadrature_lists, const std::vector<bool>& free_mask,
              double cell_volume_mm3, double cell_mm, const BalanceSettings& settings);

  /// What a frame's volume step did.
  struct Report {
    double volume_mm3 = kNaN, ratio = kNaN, ratio_before = kNaN, correction = kNaN, stop = kNaN;
  };
  static constexpr ReportEntry<Report> kReport[] = {
      {"volume_mm3", "mm^3", "muscle volume outside the bones, after the correction", &Report::volume_mm3},
      {"volume_ratio", "1", "volume / rest volume, after the correction", &Report::ratio},
      {"volume_ratio_before", "1", "volume / rest volume as carried, before the correction", &Report::ratio_before},
      {"volume_correction", "1", "δ: the free kernels' weights are λ⁰ + δ |λ⁰|", &Report::correction},
      {"volume_stop", "1", "why the correction stopped: 0 within tolerance, 1 iteration cap, 2 correction bound, 3 off",
       &Report::stop},
  };

  void run(MuscleState& state, const FrameInput& input) override;
  void appendReport(std::vector<double>& values) const override { appendTable(kReport, report_, values); }
  /// V_rest (mm³).
  double getRestVolume() const { return balance_.getRestVolume(); }

 private:
  NeighbourLists lists_;
  VolumeBalance balance_;
  Report report_;
};

}  // namespace rbfmuscle
