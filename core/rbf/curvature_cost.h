#pragma once
/// @file
/// The curvature-preservation cost of the dynamics and its gradient with
/// respect to the Gaussian centres.
#include "rbf/gaussian_field.h"

#include <Eigen/Core>

#include <vector>

namespace rbfmuscle {

/// Quadrature of C = ∫_Ω (κ(x) − κ₀(x))² dx over points q (3×M, mm, muscle
/// frame M) with weights w_q (mm³) and target mean curvatures κ₀_q
/// (field unit / mm²):
///   C = Σ_q w_q (κ(q) − κ₀_q)²,
///   ∇_ξₖ C = 2 Σ_q w_q (κ(q) − κ₀_q) ∂κ(q)/∂ξₖ,
///   ∂κ(q)/∂ξₖ = (4/3) αₖ² λₖ φₖ (q − ξₖ)(2αₖ rₖ² − 5),
/// with κ and the cut-off as in GaussianField.
///
/// Neighbour lists: each point keeps the centres within their cut-off radius plus
/// kNeighbourSkinMm (GaussianField::findNearCentres), rebuilt only when the points, the
/// shapes, the cut-off or the number of centres change, or a centre has moved more than the
/// skin since the lists were built. In between, an evaluation tests only the listed centres:
/// the same active centres in the same order, so the same numbers bitwise, without the grid
/// searches that took about 45 % of a hip frame.
///
/// Determinism: the points are split into blocks fixed by M alone; each block
/// sums its points in order into its own buffer, and the blocks are reduced
/// in block order, so results are bitwise identical whatever the OpenMP
/// thread count or schedule. The calc methods reuse internal buffers: one
/// object must not be used from two threads at once.
class CurvatureCost {
 public:
  /// How far (mm) centres may move before the neighbour lists are rebuilt.
  static constexpr double kNeighbourSkinMm = 1.0;

  /// @param points_mm quadrature points q (3×M, mm)
  /// @param weights_mm3 quadrature weights w (M, mm³, finite and ≥ 0)
  /// @param target_curvatures κ₀ (M, field unit / mm², finite)
  /// @throws std::invalid_argument on size mismatch or a bad value (names the index).
  CurvatureCost(const Eigen::Matrix3Xd& points_mm, const Eigen::VectorXd& weights_mm3,
                const Eigen::VectorXd& target_curvatures);

  /// The cost whose targets are the field's own curvatures, κ₀ = κ(Q), so C = 0
  /// for that field.
  static CurvatureCost fromField(const GaussianField& field, const Eigen::Matrix3Xd& points_mm,
                                 const Eigen::VectorXd& weights_mm3);
  /// κ(q) for every quadrature point (M): the targets κ₀ of fromField().
  static Eigen::VectorXd calcTargetCurvatures(const GaussianField& field,
                                              const Eigen::Matrix3Xd& points_mm);

  /// Moves the quadrature points (3×M, M unchanged), keeping weights and
  /// targets: the dynamics carries them with the motion.
  /// @throws std::invalid_argument on size mismatch or non-finite point.
  void setPoints(const Eigen::Matrix3Xd& points_mm);
  /// Replaces κ₀ (M).  @throws std::invalid_argument on size mismatch or non-finite value.
  void setTargetCurvatures(const Eigen::VectorXd& target_curvatures);

  /// Quadrature points q (3×M, mm).
  const Eigen::Matrix3Xd& getPoints() const { return points_mm_; }
  /// Quadrature weights w (M, mm³).
  const Eigen::VectorXd& getWeights() const { return weights_mm3_; }
  /// Target curvatures κ₀ (M, field unit / mm²).
  const Eigen::VectorXd& getTargetCurvatures() const { return target_curvatures_; }
  /// Number of quadrature points M.
  int getNumPoints() const { return static_cast<int>(points_mm_.cols()); }

  /// C = Σ_q w_q (κ(q) − κ₀_q)²  ((field unit)² / mm).
  double calcCost(const GaussianField& field) const;
  /// C, and ∇_ξ C into grad_wrt_centres (resized to 3×N, (field unit)² / mm²),
  /// column k = ∇_ξₖ C.
  double calcCostAndGradient(const GaussianField& field, Eigen::Matrix3Xd& grad_wrt_centres) const;

 private:
  /// Number of points per block, a function of M only.
  Eigen::Index findBlockSize() const;
  /// Shared kernel: fills block_cost_ and, when `with_gradient`, block_gradients_.
  void accumulateBlocks(const GaussianField& field, bool with_gradient) const;
  /// Whether the neighbour lists hold every centre of `field` active at every point.
  bool listsAreValid(const GaussianField& field) const;

  Eigen::Matrix3Xd points_mm_;
  Eigen::VectorXd weights_mm3_;
  Eigen::VectorXd target_curvatures_;
  mutable Eigen::VectorXd block_cost_;          ///< per block Σ w (κ − κ₀)²
  mutable Eigen::Matrix3Xd block_gradients_;    ///< 3 × (N · blocks), block b at columns b·N …
  mutable std::vector<std::vector<int>> near_;  ///< per block, its points' neighbour lists one after another
  mutable std::vector<std::vector<int>> near_start_;  ///< per block, where each point's list starts (size + 1)
  mutable bool lists_built_ = false;            ///< false until built, and after setPoints
  mutable Eigen::Matrix3Xd listed_centres_mm_;  ///< centres when the lists were built
  mutable Eigen::VectorXd listed_shapes_;       ///< shapes then
  mutable double listed_cutoff_ = 0.0;          ///< cut-off then
};

}  // namespace rbfmuscle
