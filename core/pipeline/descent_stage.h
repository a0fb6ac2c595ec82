// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Stage 2: the free kernels descend on the curvature objective from where the tissue map
/// put them.
#include "dynamics/curvature_objective.h"
#include "dynamics/lbfgs.h"
#include "pipeline/frame_stage.h"

#include <memory>

namespace rbfmuscle {

/// Settings of the descent.
struct DescentSettings {
  int max_iterations = 1;        ///< L-BFGS steps per frame (0: no descent)
  double cost_tolerance = 1e-3;  ///< stop when a step lowers E by less than this fraction
  double regularisation = 1e-2;  ///< ρ: pull of each free kernel towards where the map put it
  int points = 500;              ///< quadrature points of the objective (a regular subset of the volume's)
};

/// Minimises CurvatureObjective over the free kernel centres (curvature_objective.h) with a
/// few L-BFGS steps; its cost and stop reason are reported.
class DescentStage final : public FrameStage {
 public:
  /// @param rest the rest field (targets κ₀ at the rest points)
  /// @param quadrature_mm the rest quadrature (3×M) and its weights (M, mm³); a regular subset
  ///   of about settings.points is used
  /// @param free_mask kernels the descent moves
  /// @throws std::invalid_argument for settings out of range.
  DescentStage(const DeformedField& rest, const Eigen::Matrix3Xd& quadrature_mm, const Eigen::VectorXd& weights_mm3,
               std::vector<bool> free_mask, const DescentSettings& settings);

  /// What a frame's descent did.
  struct Report {
    double cost = kNaN;        ///< E at the end
    double iterations = kNaN;  ///< L-BFGS steps
    double stop = kNaN;        ///< LbfgsStop as a number
  };
  static constexpr ReportEntry<Report> kReport[] = {
      {"curvature_cost", "1",
       "the descent's objective at its end: Σ w (κ − κ₀)² / Σ w κ₀² plus the pull towards the carried kernels",
       &Report::cost},
      {"descent_iterations", "1", "L-BFGS steps taken this frame", &Report::iterations},
      {"descent_stop", "1",
       "why the descent stopped: 0 gradient tolerance, 1 cost tolerance, 2 iteration cap, 3 line search, 4 non-finite",
       &Report::stop},
  };

  bool isNeeded(const FrameInput&) const override { return settings_.max_iterations > 0; }
  void run(MuscleState& state, const FrameInput& input) override;
  void appendReport(std::vector<double>& values) const override { appendTable(kReport, report_, values); }

 private:
  DescentSettings settings_;
  std::vector<int> subset_;       ///< indices of the objective's points among the quadrature
  std::vector<int> free_kernels_; ///< indices of the free kernels
  std::unique_ptr<CurvatureObjective> objective_;
  LbfgsMinimiser minimiser_;
  Eigen::Matrix3Xd points_mm_, centres_mm_, gradient_;
  Eigen::VectorXd x_;
  Report report_;
};

}  // namespace rbfmuscle
