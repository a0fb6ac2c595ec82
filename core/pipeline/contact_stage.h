// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Stage 1: the bones near the muscle, posed for the frame.
#include "collision/bone_clearance.h"
#include "pipeline/frame_stage.h"

namespace rbfmuscle {

/// Poses the contact bones (bone_clearance.h): the muscle is min(f̃, s) from here on, so
/// every later stage sees it outside the bones. A bone whose posed box misses the region the muscle can reach this frame (its rest
/// box moved by each of its bones, padded) is not sampled at all.
class ContactStage final : public FrameStage {
 public:
  /// @param rest_box_M the muscle's rest box (M, mm), padded by the reach of its kernels
  ContactStage(BoneClearance clearance, const Eigen::AlignedBox3d& rest_box_M);

  /// What a frame's contacts did.
  struct Report {
    double near_bones = kNaN;   ///< bones sampled this frame
  };
  static constexpr ReportEntry<Report> kReport[] = {
      {"near_bones", "1", "bones whose posed box meets the region the muscle can reach this frame",
       &Report::near_bones},
  };

  void run(MuscleState& state, const FrameInput& input) override;
  void appendReport(std::vector<double>& values) const override { appendTable(kReport, report_, values); }

 private:
  BoneClearance clearance_;
  Eigen::AlignedBox3d rest_box_M_;
  Report report_;
};

}  // namespace rbfmuscle
