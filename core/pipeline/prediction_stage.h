// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Stage 2: the kernels and the quadrature points carried by the tissue map.
#include "dynamics/attachment.h"
#include "dynamics/tissue_lattice.h"
#include "pipeline/frame_stage.h"

#include <memory>

namespace rbfmuscle {

/// Carries the kernels (centre and frame F, attached kernels rigid with their bone) and the
/// quadrature points with the bones (tissue_lattice.h), samples the bones' clearance at the
/// quadrature points, and resets the weights to the rest
/// fit: every frame is a function of the bone poses alone, so nothing drifts and a frame
/// reached in one step equals one reached in many.
class PredictionStage final : public FrameStage {
 public:
  /// @param lattice the tissue map (shared with the stages that carry other points)
  /// @param rest_centres_mm kernel centres at rest (3×N), `attachments` their bones
  /// @param quadrature_mm quadrature points at rest (3×M), nodes of the lattice
  /// @param rest_weights λ of the fit (N)
  /// @throws std::invalid_argument if a quadrature point is not a lattice node.
  PredictionStage(std::shared_ptr<TissueLattice> lattice, const Eigen::Matrix3Xd& rest_centres_mm,
                  const Attachments& attachments, const Eigen::Matrix3Xd& quadrature_mm,
                  const Eigen::VectorXd& rest_weights);

  /// What a frame's prediction did.
  struct Report {
    double clamped_frames = kNaN;      ///< kernels whose frame the stretch limits clamped
    double blend_volume_change_min = kNaN;  ///< smallest det DΦ of the bone blend
    double blend_volume_change_max = kNaN;  ///< largest det DΦ of the bone blend
    double bone_overlap_max_mm = kNaN; ///< deepest quadrature point inside a bone (mm)
    double lift_fraction = kNaN;       ///< how far the shortened muscle lifts off its joint
    double lift_max_mm = kNaN;         ///< largest rise of the tissue off the joint (mm)
  };
  static constexpr ReportEntry<Report> kReport[] = {
      {"clamped_frames", "1", "kernels whose frame F the stretch limits clamped (where the blend folds)",
       &Report::clamped_frames},
      {"blend_volume_change_min", "1", "smallest volume change det DΦ of the bone blend, before thinning",
       &Report::blend_volume_change_min},
      {"blend_volume_change_max", "1", "largest volume change det DΦ of the bone blend, before thinning",
       &Report::blend_volume_change_max},
      {"bone_overlap_max_mm", "mm",
       "deepest quadrature point inside a bone: the part of the muscle the bone takes away",
       &Report::bone_overlap_max_mm},
      {"lift_fraction", "1",
       "how far the shortened muscle lifts off its joint towards its fibres' strings (0: not shortened, or no lift-off)",
       &Report::lift_fraction},
      {"lift_max_mm", "mm", "largest rise of the tissue off the joint", &Report::lift_max_mm},
  };

  void run(MuscleState& state, const FrameInput& input) override;
  void appendReport(std::vector<double>& values) const override { appendTable(kReport, report_, values); }

 private:
  std::shared_ptr<TissueLattice> lattice_;
  LatticeBinding kernels_;
  std::vector<int> quadrature_nodes_;  ///< lattice node of each quadrature point
  Eigen::VectorXd rest_weights_;
  Eigen::Matrix3Xd centres_mm_;
  std::vector<Eigen::Matrix3d> frames_;
  Eigen::VectorXd node_volume_changes_;
  Report report_;
};

}  // namespace rbfmuscle
