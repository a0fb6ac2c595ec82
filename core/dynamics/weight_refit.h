#pragma once
/// @file
/// Carrying the rest field with the bones by refitting the weights λ each frame.
///
/// Design choice (issue 4, large hip flexion): the dual-quaternion blend stretches
/// the region between the bones (local stretch 1.1–2.7 at 80° flexion). Centres
/// that keep their rest λ and α but are pulled apart further than their width
/// leave gaps, and the surface tears into pieces; raising b for the volume adds
/// islands, widening the Gaussians inflates the volume. Instead the muscle's
/// implicit function is carried with the bones, f = f₀ ∘ P⁻¹ (P the prediction),
/// and λ is refitted to it with the predicted centres fixed: the weights take
/// up the stretch, so the carried surface stays one piece.
#include "dynamics/attachment.h"
#include "dynamics/motion_prediction.h"
#include "fit/design_matrix.h"
#include "rbf/gaussian_field.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace rbfmuscle {

/// Settings of the weight refit.
struct RefitSettings {
  /// false (default): λ keeps its rest values (the prediction alone moves the field).
  /// Off by default because, measured on the hip scene (gluteus 1000 centres, 10° steps),
  /// it leaves the volume correction short (volume ratio 1.063 at a frame), while it only
  /// partly cures the splitting it was made for (tiny pinched pieces remain at 10–40°).
  bool enabled = false;
  /// Wanted number of rest samples y_j (a grid over {f₀ > −β_s}, see quadrature.h), ≥ 8.
  int sample_count = 8000;
  /// β_s (field unit): samples are the grid nodes with f₀ > −β_s; < τ = −b_rest
  /// (5 mm for a clamped signed distance), so the shell around the surface is
  /// sampled and no island rises there.
  double sample_band = 4.5;
  /// Ridge μ relative to the mean squared column norm of the design matrix:
  /// μ = ridge · mean_k ‖A(:,k)‖² (dimensionless, > 0). Pulls λ towards the previous frame's λ.
  double ridge = 1e-3;
  /// s (field unit, ≥ 0): sample j has weight w_j = 1 / (1 + (f₀(y_j)/s)²), so the
  /// samples near the surface count most (s = 0: all weights 1). Measured on the gluteus
  /// (300 centres, 0→80°): s = 1 or 0.3 gave more detached pieces than s = 0, so 0 is the default.
  double surface_width = 0.0;
  int max_iterations = 30;    ///< conjugate-gradient cap per frame, ≥ 1
  double tolerance = 1e-4;    ///< CG stops at ‖r‖ ≤ tolerance · ‖Aᵀy‖ (relative, > 0)
  /// true: the attached centres' λ are refitted too; false: they keep their rest λ
  /// (they move rigidly with their bone, where the region moves rigidly).
  bool refit_attached = false;
};

/// What one refit did.
struct WeightRefitReport {
  int samples = 0;                 ///< number of samples y_j
  int refitted_centres = 0;        ///< number of λ solved for
  long long nonzeros = 0;          ///< nonzeros of the design matrix
  RefitReport solve;               ///< CG iterations, relative residual, whether the tolerance was reached
  double rms_residual_before = 0;  ///< √(Σ_j w_j (f(z_j) − f₀(y_j))² / Σ_j w_j) with the previous λ (field unit)
  double rms_residual_after = 0;   ///< the same after the refit (field unit)
};

/// Refits the weights so that the field at the carried samples matches the rest values.
///
/// Rest samples y_j (grid nodes with f₀(y_j) > −β_s, cell volume ignored) with
/// values f₀(y_j) and blend weights (attachment.h) are fixed at construction. Each
/// frame they are carried by the prediction, z_j = P(y_j), and with the centres,
/// shapes and b fixed, the refitted weights λ_R (R = free centres, or all) solve
///   min_λ Σ_j w_j (b + Σ_k λ_k φ_k(z_j) − f₀(y_j))² + μ ‖λ_R − λ_R^prev‖²
/// by Jacobi-PCG (fit/design_matrix.h) on δ = λ_R − λ_R^prev from δ = 0 (warm
/// start), with the cut-off of the field (φ_k(z_j) = 0 where centre k is inactive).
/// At identity motion with the rest centres, the residual is zero and λ is kept.
/// Deterministic: identical inputs give bitwise identical weights.
class WeightRefit {
 public:
  /// @param rest_field f₀ (its offset must be < −sample_band)
  /// @param attachments bone of every centre  @param blend_length_mm ℓ of the blend weights
  /// @throws std::invalid_argument for bad settings (names the field) or as makeQuadrature.
  WeightRefit(const GaussianField& rest_field, const Attachments& attachments, const RefitSettings& settings,
              double blend_length_mm);

  /// Carries the samples with `transforms` and refits the weights of `field` (same N as the
  /// rest field; centres, shapes and offset as they are now). Sets the field's weights.
  /// @throws std::invalid_argument if N differs.
  WeightRefitReport run(GaussianField& field, const std::vector<DualQuaternion>& transforms);

  /// Rest samples y_j (3×S, mm, M).
  const Eigen::Matrix3Xd& getRestSamples() const { return rest_samples_mm_; }
  /// Carried samples z_j of the last run (3×S, mm, M).
  const Eigen::Matrix3Xd& getSamples() const { return samples_mm_; }
  /// Targets f₀(y_j) (S, field unit).
  const Eigen::VectorXd& getTargets() const { return targets_; }
  /// The settings.
  const RefitSettings& getSettings() const { return settings_; }

 private:
  RefitSettings settings_;
  Eigen::Matrix3Xd rest_samples_mm_;
  Eigen::Matrix3Xd samples_mm_;
  Eigen::VectorXd targets_;
  Eigen::VectorXd row_scales_;         ///< √w_j (S)
  Eigen::MatrixXd sample_weights_;     ///< B×S blend weights of the rest samples
  std::vector<int> column_of_centre_;  ///< column of centre k in the design matrix, −1 if λ_k is kept
  std::vector<int> refitted_;          ///< centre of each column
  std::vector<ActiveCentres> active_;  ///< active centres at each sample (scratch)
  std::vector<std::vector<int>> rows_;        ///< rows of each column (scratch)
  std::vector<std::vector<double>> values_;   ///< φ of each column (scratch)
  Eigen::VectorXd rhs_, fixed_, product_, delta_, weights_;
};

}  // namespace rbfmuscle
