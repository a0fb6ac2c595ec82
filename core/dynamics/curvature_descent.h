#pragma once
/// @file
/// Descent of the free centres on the curvature-preservation cost with the
/// dissertation's regularisation towards the predicted positions.
#include "rbf/curvature_cost.h"
#include "rbf/gaussian_field.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace rbfmuscle {

/// Why a descent stopped.
enum class DescentStop {
  kGradientTolerance,  ///< ‖∇E‖ ≤ gradient_tolerance · ‖∇E₀‖ (or ∇E = 0 at start)
  kCostTolerance,      ///< relative decrease (E_prev − E)/E_prev < cost_tolerance
  kIterationCap,       ///< max_iterations reached
  kLineSearchFailed,   ///< no step of the line search lowered E (E is at a numerical minimum)
  kNonFinite,          ///< the cost or gradient at the start was not finite (centres untouched)
  kNoFreeCentres,      ///< nothing to move
};

/// Human-readable name of a stop reason ("gradient_tolerance", "cost_tolerance",
/// "iteration_cap", "line_search_failed", "non_finite", "no_free_centres").
std::string toString(DescentStop stop);

/// Settings of the descent.
struct DescentSettings {
  /// ρ (dimensionless): weight of the regulariser (see CurvatureDescent).
  double regularisation = 1e-2;
  /// ℓ_reg (mm): length over which the regulariser equals ρ per free centre.
  double regularisation_length_mm = 1.0;
  int max_iterations = 50;          ///< iteration cap, ≥ 1
  double cost_tolerance = 1e-5;     ///< stop when the relative decrease of one iteration is below this
  double gradient_tolerance = 1e-4; ///< stop when ‖∇E‖ ≤ this · ‖∇E₀‖
  double initial_step_mm = 0.5;     ///< first step moves the free centre of largest gradient by this (mm)
  int lbfgs_memory = 8;             ///< L-BFGS pairs kept, ≥ 0 (0 = steepest descent)
  int max_backtracks = 30;          ///< Armijo halvings per iteration
  double armijo = 1e-4;             ///< sufficient-decrease constant c₁ ∈ (0, 1)
};

/// What a descent did.
struct DescentReport {
  int iterations = 0;            ///< accepted steps
  int evaluations = 0;           ///< cost(+gradient) evaluations
  double cost_initial = 0.0;     ///< E at the start (normalised, dimensionless)
  double cost_final = 0.0;       ///< E at the end, ≤ cost_initial
  double curvature_cost_final = 0.0;  ///< the curvature part Σ w (κ − κ₀)² / E_ref at the end
  double gradient_norm_initial = 0.0; ///< ‖∇E₀‖ (1/mm)
  double gradient_norm_final = 0.0;   ///< ‖∇E‖ at the end (1/mm)
  DescentStop stop_reason = DescentStop::kIterationCap;
};

/// Minimises over the free centres ξ_F (attached centres and λ, α, b fixed)
///   E(ξ) = Σ_q w_q (κ(q) − κ₀_q)² / E_ref + (ρ / (|F| ℓ_reg²)) Σ_{k∈F} ‖ξₖ − ξₖ^pred‖²,
/// E_ref = Σ_q w_q κ₀_q² (set at construction, so E is dimensionless and one
/// default step and tolerance fit every muscle; if E_ref = 0 then E_ref = Σ w_q).
/// The regulariser is the dissertation's idea of keeping the centres near where
/// the motion puts them (it removes the null directions of the curvature cost,
/// e.g. a centre far from every quadrature point).
///
/// Method: L-BFGS (two-loop recursion, memory m) with Armijo backtracking; the
/// first step and any step after a non-descent direction is steepest descent
/// scaled so the largest centre move is initial_step_mm. A trial with a non-finite
/// cost counts as a failed trial (the step is halved). Every accepted step lowers
/// E, so E never increases; on kNonFinite or kLineSearchFailed the best centres
/// found are kept. Deterministic (CurvatureCost is bitwise deterministic).
/// Preallocated: run() does not allocate once sized for one N (the field's grids do not).
class CurvatureDescent {
 public:
  /// @param cost quadrature (kept by reference: it must outlive this object; its points may move)
  /// @param free_mask size N, true for the centres the descent moves
  /// @throws std::invalid_argument for bad settings (names the field) or an empty mask size.
  CurvatureDescent(const CurvatureCost& cost, std::vector<bool> free_mask, const DescentSettings& settings);

  /// Runs the descent from the field's current centres with anchors ξ^pred (3×N,
  /// only free columns used), writing the result into `field` (setCentrePositions).
  /// @throws std::invalid_argument if N differs from the mask.
  DescentReport run(GaussianField& field, const Eigen::Matrix3Xd& anchors_mm);

  /// E(ξ) and ∇E (3×N, zero in attached columns) for the field's centres, without moving them.
  double calcObjective(const GaussianField& field, const Eigen::Matrix3Xd& anchors_mm,
                       Eigen::Matrix3Xd& gradient) const;
  /// E_ref (see class comment).
  double getReferenceEnergy() const { return reference_energy_; }
  /// The settings.
  const DescentSettings& getSettings() const { return settings_; }

 private:
  const CurvatureCost& cost_;
  std::vector<bool> free_mask_;
  DescentSettings settings_;
  double reference_energy_ = 1.0;
  int num_free_ = 0;
  // Work buffers (3×N) and L-BFGS history.
  mutable Eigen::Matrix3Xd cost_gradient_;
  mutable double last_curvature_cost_ = 0.0;  ///< curvature part of the last calcObjective
  Eigen::Matrix3Xd x_, g_, x_trial_, g_trial_, direction_;
  std::vector<Eigen::Matrix3Xd> s_hist_, y_hist_;
  std::vector<double> rho_hist_, alpha_hist_;
};

}  // namespace rbfmuscle
