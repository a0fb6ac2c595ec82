// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// The descent's objective: keep the rest curvature at the carried quadrature points, and
/// keep the free kernels near where the tissue map puts them.
#include "rbf/deformed_field.h"
#include "rbf/neighbour_lists.h"

#include <Eigen/Core>

#include <vector>

namespace rbfmuscle {

/// E(ξ) = Σ_q w_q (κ(y_q) − κ₀_q)² / E_ref + (ρ / (|F| ℓ²)) Σ_{k∈F} ‖ξₖ − ξₖ^anchor‖²
/// over the free kernels F (the others fixed), with κ = ∇²f / 3 of the deformed field at the
/// carried quadrature points y_q (rest weights w_q, mm³; rest targets κ₀_q), E_ref = Σ w κ₀²
/// (so E is dimensionless and one tolerance fits every muscle), ρ the regularisation and ℓ
/// its length (mm). With d = y − ξ, A the kernel's metric, φ = exp(−dᵀAd) and
/// g = 4|Ad|² − 2 tr A:
///   κ = (1/3) Σ λ φ g,   ∂κ/∂ξ = (λ/3) φ (2 g A d − 8 A A d).
/// Each quadrature point sums over its rest neighbour list (neighbour_lists.h), in list order,
/// so results are deterministic. Not thread-safe (scratch).
class CurvatureObjective {
 public:
  /// @param weights_mm3 w_q (M, ≥ 0)  @param targets κ₀_q (M)  @param lists the points' kernels
  /// @param free_mask N flags, true where the kernel may move
  /// @param regularisation ρ ≥ 0  @param regularisation_length_mm ℓ > 0
  /// @throws std::invalid_argument on sizes or values out of range.
  CurvatureObjective(Eigen::VectorXd weights_mm3, Eigen::VectorXd targets, NeighbourLists lists,
                     std::vector<bool> free_mask, double regularisation, double regularisation_length_mm = 1.0);

  /// κ at each point (M) of `points_mm` for `field`: the targets of a rest field.
  static Eigen::VectorXd calcCurvatures(const DeformedField& field, const Eigen::Matrix3Xd& points_mm,
                                        const NeighbourLists& lists);

  /// E for `field` with quadrature points at `points_mm` (3×M) and anchors (3×N); with a
  /// gradient pointer, ∇_ξ E (3×N, zero for fixed kernels).
  double evaluate(const DeformedField& field, const Eigen::Matrix3Xd& points_mm, const Eigen::Matrix3Xd& anchors_mm,
                  Eigen::Matrix3Xd* gradient) const;

 private:
  struct Term {  ///< one active kernel at the current point
    int kernel;
    double phi, g;
    Eigen::Vector3d ad;
  };
  Eigen::VectorXd weights_mm3_;
  Eigen::VectorXd targets_;
  NeighbourLists lists_;
  std::vector<bool> free_mask_;
  int num_free_ = 0;
  double reference_ = 1.0;
  double anchor_weight_ = 0.0;  ///< ρ / (|F| ℓ²)
  mutable std::vector<Term> terms_;
};

}  // namespace rbfmuscle
