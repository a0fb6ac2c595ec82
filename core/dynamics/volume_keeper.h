#pragma once
/// @file
/// Measuring the volume of {f > 0} and holding it at the rest value by the offset b.
#include "rbf/gaussian_field.h"

#include <Eigen/Core>

#include <string>

namespace rbfmuscle {

/// Settings of the volume measure and correction.
struct VolumeSettings {
  /// w (field unit, mm for a signed-distance fit): width of the smoothed Heaviside
  /// H(f) = ½(1 + tanh(f / w)); ≤ 0 means "half the quadrature cell size, h/2" (the
  /// smoothing biases V by O(w² · area · mean curvature), ~1 % on a 10 mm sphere; the
  /// ratio V/V_rest, measured the same way, is what the correction holds).
  double heaviside_width = 0.0;
  double tolerance = 1e-3;     ///< stop when |V/V_rest − 1| ≤ this
  int max_iterations = 20;     ///< Newton/bisection cap, ≥ 1
  /// Largest total change of b from its rest value (field unit, ≈ mm across the surface of a signed-distance fit).
  double max_offset_change = 2.5;
  bool enabled = true;         ///< false: measure only, never change b
};

/// Why the volume correction stopped.
enum class VolumeStop {
  kWithinTolerance,  ///< |V/V_rest − 1| ≤ tolerance
  kIterationCap,     ///< max_iterations reached (best b kept)
  kOffsetBound,      ///< the bound on b was reached (best b kept)
  kDisabled,         ///< correction disabled: measured only
};

/// Name of a stop reason ("within_tolerance", "iteration_cap", "offset_bound", "disabled").
std::string toString(VolumeStop stop);

/// What the volume step did.
struct VolumeReport {
  double volume_mm3 = 0.0;       ///< V after the correction (mm³)
  double volume_ratio = 0.0;     ///< V / V_rest after the correction
  double volume_ratio_before = 0.0;  ///< V / V_rest before it
  double offset = 0.0;           ///< b used (field unit)
  int iterations = 0;            ///< field-value passes after the first
  VolumeStop stop_reason = VolumeStop::kWithinTolerance;
};

/// Volume of the inside by quadrature over carried points: with rest points x_j
/// (a grid of cell volume h³ covering {f > −β} at rest, see quadrature.h), their
/// current positions y_j = P(x_j) and J_j = det ∂P/∂x at x_j (change of variables),
///   V(b) = Σ_j h³ J_j H(f_b(y_j)),  H(f) = ½(1 + tanh(f/w)),
/// where f_b = f with offset b. V is smooth and strictly increasing in b
/// (dV/db = Σ h³ J_j H'(f_b(y_j)) > 0), and b does not change the curvature κ, so this
/// correction leaves the curvature cost untouched. The correction solves
/// V(b) = V_rest by safeguarded Newton (bisection whenever Newton leaves the
/// bracket) within b_rest ± max_offset_change. Each pass reuses the Σλφ part:
/// f_b(y) = (f(y) − b_old) + b, so one field evaluation per frame suffices.
class VolumeKeeper {
 public:
  /// @param rest_points_mm x_j (3×M)  @param cell_volume_mm3 h³ > 0
  /// @param rest_field the field at rest: sets b_rest and V_rest = V(b_rest) with J = 1
  /// @throws std::invalid_argument for bad settings, h³ ≤ 0 or V_rest ≤ 0.
  VolumeKeeper(const Eigen::Matrix3Xd& rest_points_mm, double cell_volume_mm3, const GaussianField& rest_field,
               const VolumeSettings& settings);

  /// Measures V for the field at `points_mm` (3×M, current y_j) with Jacobians J (M) and,
  /// if enabled, sets the field's offset so V = V_rest within the tolerance.
  /// @throws std::invalid_argument on size mismatch.
  VolumeReport correct(GaussianField& field, const Eigen::Matrix3Xd& points_mm, const Eigen::VectorXd& jacobians);

  /// V(b) for the current field at `points_mm` with Jacobians, no correction (mm³).
  double calcVolume(const GaussianField& field, const Eigen::Matrix3Xd& points_mm,
                    const Eigen::VectorXd& jacobians) const;

  /// V_rest (mm³).
  double getRestVolume() const { return rest_volume_mm3_; }
  /// b_rest (field unit).
  double getRestOffset() const { return rest_offset_; }
  /// w actually used (field unit).
  double getHeavisideWidth() const { return width_; }

 private:
  /// Σ h³ J H(s + b) over precomputed s_j = f(y_j) − b, and its b-derivative.
  double sumVolume(double offset, const Eigen::VectorXd& jacobians, double* derivative) const;

  double cell_volume_mm3_;
  VolumeSettings settings_;
  double width_;
  double rest_offset_;
  double rest_volume_mm3_ = 0.0;
  mutable Eigen::VectorXd sums_;  ///< s_j = f(y_j) − b (field unit)
};

}  // namespace rbfmuscle
