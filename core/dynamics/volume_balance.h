// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// The muscle's volume by quadrature over carried points, held at its rest value by one
/// scalar per frame.
#include "rbf/deformed_field.h"
#include "rbf/neighbour_lists.h"

#include <Eigen/Core>

#include <functional>
#include <string>
#include <vector>

namespace rbfmuscle {

/// Settings of VolumeBalance.
struct BalanceSettings {
  /// Width w of the smoothed step H(f) = ½(1 + tanh(f/w)) (field unit ≈ mm); ≤ 0: half the
  /// quadrature cell. The ratio V/V_rest, measured the same way at rest and now, is what is held.
  double step_width = 0.0;
  double tolerance = 1e-3;     ///< stop when |V/V_rest − 1| ≤ this
  int max_iterations = 30;     ///< Newton/bisection steps at most, ≥ 1
  double max_correction = 0.5; ///< |δ| at most (class comment)
  bool enabled = true;         ///< false: measure only
};

/// Why the volume step stopped.
enum class BalanceStop { kWithinTolerance, kIterationCap, kCorrectionBound, kDisabled };
/// "within_tolerance", "iteration_cap", "correction_bound", "disabled".
std::string toString(BalanceStop stop);

/// What a frame's volume step did.
struct BalanceReport {
  double volume_mm3 = 0.0;           ///< V after the correction (mm³)
  double ratio = 0.0;                ///< V / V_rest after it
  double ratio_before = 0.0;         ///< V / V_rest before it
  double correction = 0.0;           ///< δ
  int iterations = 0;                ///< Newton/bisection steps
  BalanceStop stop = BalanceStop::kWithinTolerance;
};

/// Where tissue folds out of a bone to a point y (pipeline/tissue_fold.h): calls
/// visit(mirror, foot, cap_mm) for each fold to y whose cap may exceed floor; f(y) is then at
/// least min(f(mirror), f(foot), cap).
using FoldFinder = std::function<void(const Eigen::Vector3d& y_mm, double floor,
                                      const std::function<void(const Eigen::Vector3d&, const Eigen::Vector3d&, double)>& visit)>;

/// V = Σ_j w_j J_j H(min(f(y_j), s_j)) over the quadrature points y_j carried from a rest grid
/// (cell volume w_j = h³, J_j the carried volume change, s_j the clearance from the bones,
/// +∞ far from them), so the volume is that of the muscle outside the bones; where tissue is
/// folded out of a bone to y_j (`folds`), f(y_j) is raised to the fold's value.
/// Correction: the free kernels' weights λₖ ← λₖ⁰ + δ cₖ with cₖ = |λₖ⁰| (0 for the others),
/// so f gains δ g, g = Σ cₖ φₖ ≥ 0 and V(δ) is non-decreasing; V(δ) = V_rest is solved by
/// safeguarded Newton within |δ| ≤ max_correction from one pass over the points (f and g
/// together). Every frame starts from δ = 0 and the rest weights.
class VolumeBalance {
 public:
  /// @param rest_weights the rest λ⁰ (N)  @param free_mask N flags (kernels whose weight corrects)
  /// @param cell_volume_mm3 h³ > 0  @param cell_mm h (the default step width is h/2)
  /// @throws std::invalid_argument on sizes or values out of range.
  VolumeBalance(const Eigen::VectorXd& rest_weights, const std::vector<bool>& free_mask, double cell_volume_mm3,
                double cell_mm, const BalanceSettings& settings = {});

  /// Sets V_rest from the rest field at the rest points (J = 1) with their clearances.
  /// @throws std::invalid_argument if V_rest ≤ 0 or sizes differ.
  void setRest(const DeformedField& rest_field, const Eigen::Matrix3Xd& points_mm, const NeighbourLists& lists,
               const Eigen::VectorXd& clearance_mm, const FoldFinder& folds = nullptr);

  /// Measures V for `field` (its weights must be the rest weights) at the carried points with
  /// volume changes J and clearances s, and (if enabled) sets the field's weights to λ⁰ + δ c.
  /// @throws std::invalid_argument on size mismatch.
  BalanceReport balance(DeformedField& field, const Eigen::Matrix3Xd& points_mm, const NeighbourLists& lists,
                       const Eigen::VectorXd& volume_changes, const Eigen::VectorXd& clearance_mm,
                       const FoldFinder& folds = nullptr);

  /// V_rest (mm³).
  double getRestVolume() const { return rest_volume_mm3_; }

 private:
  /// Σ w J H(min(f + δ g, s)) and its δ-derivative from the stored f_j, g_j.
  double sum(double delta, const Eigen::VectorXd& volume_changes, const Eigen::VectorXd& clearance_mm,
             double* derivative) const;

  Eigen::VectorXd rest_weights_;
  Eigen::VectorXd correction_weights_;
  double cell_volume_mm3_;
  double width_;
  BalanceSettings settings_;
  double rest_volume_mm3_ = 0.0;
  /// f and g at a fold's mirror and foot, and its cap: the fold's value is the smallest of three lines in δ.
  struct FoldLines {
    int point;
    double mirror_value, mirror_correction, foot_value, foot_correction, cap_mm;
  };
  /// f_j and g_j at the points, and at those of their folds that can win, for this frame.
  void sumValues(const DeformedField& field, const Eigen::Matrix3Xd& points, const NeighbourLists& lists,
                 const Eigen::VectorXd& clearance_mm, const FoldFinder& folds);

  static constexpr long kBlock = 256;     ///< points per shared block (parallel_blocks.h)
  Eigen::VectorXd values_, corrections_;  ///< f_j, g_j of the current frame
  std::vector<FoldLines> folds_;          ///< the current frame's folds, sorted by point
};

}  // namespace rbfmuscle
