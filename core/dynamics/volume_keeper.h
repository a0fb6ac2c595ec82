#pragma once
/// @file
/// Measuring the volume of {f > 0} and holding it at the rest value through the
/// weights of the free centres.
#include "rbf/gaussian_field.h"

#include <Eigen/Core>

#include <string>
#include <vector>

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
  /// Largest |δ|, the correction's relative change of the corrected weights (class comment).
  double max_correction = 0.5;
  bool enabled = true;         ///< false: measure only, never change the field
};

/// Why the volume correction stopped.
enum class VolumeStop {
  kWithinTolerance,  ///< |V/V_rest − 1| ≤ tolerance
  kIterationCap,     ///< max_iterations reached (best b kept)
  kCorrectionBound,  ///< the bound on δ was reached (best δ kept)
  kDisabled,         ///< correction disabled: measured only
};

/// Name of a stop reason ("within_tolerance", "iteration_cap", "correction_bound", "disabled").
std::string toString(VolumeStop stop);

/// What the volume step did.
struct VolumeReport {
  double volume_mm3 = 0.0;       ///< V after the correction (mm³)
  double volume_ratio = 0.0;     ///< V / V_rest after the correction
  double volume_ratio_before = 0.0;  ///< V / V_rest before it
  double correction = 0.0;       ///< δ now applied (dimensionless)
  int iterations = 0;            ///< field-value passes after the first
  VolumeStop stop_reason = VolumeStop::kWithinTolerance;
};

/// Volume of the inside by quadrature over carried points: with rest points x_j
/// (a grid of cell volume h³ covering {f > −β} at rest, see quadrature.h), their
/// current positions y_j = P(x_j) and J_j = det ∂P/∂x at x_j (change of variables),
///   V = Σ_j h³ J_j H(f(y_j)),  H(f) = ½(1 + tanh(f/w)).
///
/// **Correction.** The weights move by δ·c: λₖ = λₖ⁰ + δ cₖ with cₖ ≥ 0 given per centre
/// (the deformer: cₖ = |λₖ rest| for free centres, 0 for attached ones), so the field
/// gains δ g(x), g = Σₖ cₖ φₖ(x) ≥ 0, and V(δ) = Σ_j h³ J_j H(f(y_j) + (δ − δ_now) g(y_j))
/// is smooth and non-decreasing in δ. correct() solves V(δ) = V_rest by safeguarded Newton
/// (bisection whenever Newton leaves the bracket) within |δ| ≤ max_correction, from one
/// evaluation of f and g per call. The offset b stays at its rest value.
/// Why not the offset b (used first): b lifts f everywhere, attachments included; the
/// iliacus, shortened and compressed by the prediction at 80° flexion, needed b + 2.2,
/// which inflated its insertion, rigid with the femur, 2 mm into the femur. A shortened
/// muscle bulges in its belly, which is where the free centres are.
/// δ changes the curvature κ, so the deformer removes it (removeCorrection) before its
/// descent, which compares κ of the uncorrected field with the rest targets κ₀.
class VolumeKeeper {
 public:
  /// @param rest_points_mm x_j (3×M)  @param cell_volume_mm3 h³ > 0
  /// @param rest_field the field at rest: V_rest = V with J = 1, δ = 0
  /// @param correction_weights c (N, ≥ 0, finite); all 0: the volume is only measured
  /// @throws std::invalid_argument for bad settings, h³ ≤ 0, V_rest ≤ 0, or c of the wrong
  ///   size or with a negative or non-finite entry.
  VolumeKeeper(const Eigen::Matrix3Xd& rest_points_mm, double cell_volume_mm3, const GaussianField& rest_field,
               const Eigen::VectorXd& correction_weights, const VolumeSettings& settings);

  /// Measures V for the field at `points_mm` (3×M, current y_j) with Jacobians J (M) and,
  /// if enabled, moves the field's weights by (δ − δ_now) c so V = V_rest within the tolerance.
  /// @throws std::invalid_argument on size mismatch.
  VolumeReport correct(GaussianField& field, const Eigen::Matrix3Xd& points_mm, const Eigen::VectorXd& jacobians);

  /// Takes the applied correction out of the field's weights (λ −= δ c); δ becomes 0, the
  /// next correct() starts its search from the δ removed.
  void removeCorrection(GaussianField& field);

  /// Forgets the correction without touching a field (its weights were reset to c-free ones):
  /// δ = 0 and the next search starts from 0.
  void forgetCorrection() { correction_ = guess_ = 0.0; }
  /// Records that the field's weights now hold δ c, moved there by someone else (the deformer's
  /// step limit takes the weights back part of the way): the next removeCorrection takes it out.
  void setAppliedCorrection(double delta) { correction_ = guess_ = delta; }

  /// V for the current field at `points_mm` with Jacobians, no correction (mm³).
  double calcVolume(const GaussianField& field, const Eigen::Matrix3Xd& points_mm,
                    const Eigen::VectorXd& jacobians) const;

  /// V_rest (mm³).
  double getRestVolume() const { return rest_volume_mm3_; }
  /// δ now applied.
  double getCorrection() const { return correction_; }
  /// w actually used (field unit).
  double getHeavisideWidth() const { return width_; }

 private:
  /// Σ h³ J H(s + (δ − δ_now) g) over precomputed s_j = f(y_j), g_j, and its δ-derivative.
  double sumVolume(double delta, const Eigen::VectorXd& jacobians, double* derivative) const;
  /// Adds d·c to the field's weights.
  void shiftWeights(GaussianField& field, double d) const;

  double cell_volume_mm3_;
  VolumeSettings settings_;
  double width_;
  double rest_volume_mm3_ = 0.0;
  Eigen::VectorXd correction_weights_;  ///< c (N)
  std::vector<int> corrected_;          ///< centres with cₖ > 0
  GaussianField correction_field_;      ///< g: the corrected centres with weights c (moved per call)
  Eigen::Matrix3Xd corrected_centres_;  ///< scratch: their current positions
  double correction_ = 0.0;             ///< δ applied
  double guess_ = 0.0;                  ///< start of the next search (the last δ)
  mutable Eigen::VectorXd values_;      ///< s_j = f(y_j)
  Eigen::VectorXd corrections_;         ///< g_j = g(y_j)
};

}  // namespace rbfmuscle
