// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// The Gaussian RBF implicit field of a muscle: value, gradient, Hessian,
/// mean curvature and their derivatives with respect to the centres.
#include "rbf/implicit_field.h"
#include "rbf/spatial_grid.h"

#include <Eigen/Core>

#include <limits>
#include <vector>

namespace rbfmuscle {

/// Field value, gradient and Hessian at one point, from one pass over the
/// active centres. NaN until computed.
struct FieldEvaluation {
  /// f(x) = b + Σᵢ λᵢ φᵢ(x)  (field unit, mm for a signed-distance fit).
  double value = std::numeric_limits<double>::quiet_NaN();
  /// ∇f = −2 Σᵢ αᵢλᵢφᵢ (x−ξᵢ)  (field unit / mm).
  Eigen::Vector3d gradient = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  /// H f = 2 Σᵢ αᵢλᵢφᵢ (2αᵢ (x−ξᵢ)(x−ξᵢ)ᵀ − I)  (field unit / mm²).
  Eigen::Matrix3d hessian = Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
};

/// The centres active at a point (φ ≥ ε), in ascending index order, with
/// their φ and squared distance. Caller-owned and reusable: a warm object does not allocate.
struct ActiveCentres {
  std::vector<int> indices;  ///< centre indices, ascending
  std::vector<double> phi;   ///< φ = exp(−α r²) of each, same order
  std::vector<double> r2_mm2; ///< r² = ‖p − ξ‖² (mm²) of each, same order
  /// Number of active centres.
  int size() const { return static_cast<int>(indices.size()); }
  /// Empties the lists, keeping their capacity.
  void clear() {
    indices.clear();
    phi.clear();
    r2_mm2.clear();
  }
};

/// Gaussian RBF field in the muscle frame M (coordinates in mm):
///   f(x) = b + Σᵢ λᵢ φᵢ(x),  φᵢ(x) = exp(−αᵢ ‖x − ξᵢ‖²),
/// with offset b, centres ξᵢ (mm), weights λᵢ (field unit) and shapes
/// αᵢ > 0 (mm⁻²). Centre i is ignored wherever φᵢ < ε (cut-off ε ∈ [0, 1),
/// default 1e-8; ε = 0 disables the cut-off), i.e. beyond the radius
/// rᵢ = √(ln(1/ε)/αᵢ): centre i is active at x iff αᵢ‖x−ξᵢ‖² ≤ ln(1/ε).
///
/// Acceleration: centres are grouped by cut-off radius into power-of-two
/// classes (r ∈ [2^(e−1), 2^e) mm), one SpatialGrid per class with cell size
/// 2^(e−1) mm, so a point visits only nearby centres whatever the mix of
/// shapes (a class whose cells would all be visited is scanned linearly). The
/// grid path and the brute-force path (setUseGrid(false), or ε = 0) apply the
/// same cut-off test and sum in ascending centre index, so they give bitwise
/// identical results.
///
/// Every calc/find method is const and thread-safe (scratch is thread-local);
/// setters are not. Query points must be finite (std::invalid_argument).
class GaussianField final : public ImplicitField {
 public:
  /// Default cut-off ε on φ.
  static constexpr double kDefaultCutoff = 1e-8;

  /// Empty field f ≡ offset_value.
  explicit GaussianField(double offset_value = 0.0, double cutoff = kDefaultCutoff);
  /// Field with the given centres (3×N, mm), weights (N) and shapes (N, mm⁻²).
  /// @throws std::invalid_argument as setCentres() and setCutoff().
  GaussianField(double offset_value, const Eigen::Matrix3Xd& centres_mm,
                const Eigen::VectorXd& weights, const Eigen::VectorXd& shapes_per_mm2,
                double cutoff = kDefaultCutoff);

  /// Replaces all centres and rebuilds the grids.
  /// @throws std::invalid_argument if sizes differ, or a centre or weight is
  ///   not finite, or a shape is not finite and > 0 (message names the index).
  void setCentres(const Eigen::Matrix3Xd& centres_mm, const Eigen::VectorXd& weights,
                  const Eigen::VectorXd& shapes_per_mm2);
  /// Appends one centre (rebuilding only its radius class); returns its index.
  /// @throws std::invalid_argument as setCentres().
  int addCentre(const Eigen::Vector3d& centre_mm, double weight, double shape_per_mm2);
  /// Moves the centres (3×N, mm; N unchanged), keeping weights and shapes:
  /// O(N) grid update, no allocation. Called by the dynamics every iteration.
  /// @throws std::invalid_argument on a size mismatch or non-finite centre.
  void setCentrePositions(const Eigen::Matrix3Xd& centres_mm);
  /// Replaces the weights λ (N).  @throws std::invalid_argument on size or non-finite.
  void setWeights(const Eigen::VectorXd& weights);
  /// Sets the offset b (field unit).
  void setOffset(double offset_value) { offset_ = offset_value; }
  /// Sets ε ∈ [0, 1) and rebuilds the grids.  @throws std::invalid_argument otherwise.
  void setCutoff(double cutoff);
  /// Chooses the grid (true, default) or the brute-force path (false); both
  /// give identical results.
  void setUseGrid(bool use_grid) { use_grid_ = use_grid; }

  /// Offset b (field unit).
  double getOffset() const { return offset_; }
  /// Centres ξ (3×N, mm).
  const Eigen::Matrix3Xd& getCentres() const { return centres_mm_; }
  /// Weights λ (N, field unit).
  const Eigen::VectorXd& getWeights() const { return weights_; }
  /// Shapes α (N, mm⁻²).
  const Eigen::VectorXd& getShapes() const { return shapes_per_mm2_; }
  /// Cut-off ε on φ.
  double getCutoff() const { return cutoff_; }
  /// Whether the grid path is selected.
  bool getUseGrid() const { return use_grid_; }
  /// Number of centres N.
  int getNumCentres() const { return static_cast<int>(centres_mm_.cols()); }
  /// Cut-off radius of centre k, √(ln(1/ε)/αₖ) (mm); +∞ when ε = 0.
  double getCutoffRadius(int k) const;

  /// Fills `out` with the centres active at p (φ ≥ ε), ascending, with φ and r².
  /// Per-centre terms (rbf/gaussian_terms.h) summed over `out` in its order
  /// reproduce this class's sums bitwise.
  void findActiveCentres(const Eigen::Vector3d& p_mm, ActiveCentres& out) const;

  /// f(p) = b + Σ λᵢ φᵢ(p).
  double calcValue(const Eigen::Vector3d& p_mm) const override;
  /// ∇f(p) (field unit / mm).
  Eigen::Vector3d calcGradient(const Eigen::Vector3d& p_mm) const override;
  /// Value, gradient and Hessian in one pass.
  FieldEvaluation calcEvaluation(const Eigen::Vector3d& p_mm) const;
  /// Mean curvature κ(p) = tr(H f)/3 = (2/3) Σ αᵢλᵢφᵢ (2αᵢ rᵢ² − 3)  (field unit / mm²).
  double calcMeanCurvature(const Eigen::Vector3d& p_mm) const;
  /// ∇ₓκ(p) = −(4/3) Σ αᵢ²λᵢφᵢ (2αᵢ rᵢ² − 5)(p−ξᵢ)  (field unit / mm³).
  Eigen::Vector3d calcMeanCurvatureGradient(const Eigen::Vector3d& p_mm) const;

  /// f at every column of points_mm (3×M); out is resized to M. Parallel
  /// (OpenMP) over points, results independent of the thread count.
  void calcValues(const Eigen::Matrix3Xd& points_mm, Eigen::VectorXd& out) const;
  /// κ at every column of points_mm (3×M); out is resized to M. Parallel as calcValues.
  void calcMeanCurvatures(const Eigen::Matrix3Xd& points_mm, Eigen::VectorXd& out) const;

  /// ∂f(p)/∂ξₖ = 2αₖλₖφₖ (p−ξₖ)  (field unit / mm); zero where centre k is cut off.
  Eigen::Vector3d calcValueDerivativeWrtCentre(const Eigen::Vector3d& p_mm, int k) const;
  /// ∂κ(p)/∂ξₖ = (4/3) αₖ²λₖφₖ (2αₖ rₖ² − 5)(p−ξₖ)  (field unit / mm³); zero where cut off.
  Eigen::Vector3d calcMeanCurvatureDerivativeWrtCentre(const Eigen::Vector3d& p_mm, int k) const;
  /// ∂κ(p)/∂λₖ = (2/3) αₖφₖ (2αₖ rₖ² − 3)  (mm⁻²); zero where cut off.
  double calcMeanCurvatureDerivativeWrtWeight(const Eigen::Vector3d& p_mm, int k) const;

 private:
  /// Centres of one cut-off radius class (r ∈ [2^(e−1), 2^e) mm).
  struct RadiusClass {
    int exponent = 0;              ///< e
    double query_radius_mm = 0.0;  ///< largest cut-off radius in the class, slightly padded
    std::vector<int> members;      ///< global centre indices, ascending
    Eigen::Matrix3Xd positions_mm; ///< centres of the members, same order
    SpatialGrid grid;              ///< over positions_mm, cell size 2^(e−1) mm
  };

  /// Checks index k, throwing std::out_of_range naming k and N.
  void checkIndex(int k) const;
  /// φₖ(p) if centre k is active at p, else 0; d and r2 receive p − ξₖ and ‖d‖².
  double findPhi(const Eigen::Vector3d& p_mm, int k, Eigen::Vector3d& d, double& r2) const;
  /// Radius class exponent of centre k.
  int findExponent(int k) const;
  /// Rebuilds every radius class from scratch.
  void rebuildClasses();
  /// Rebuilds the positions and grid of one class.
  void rebuildClass(RadiusClass& rc);
  /// Calls visit(k, phi, d, r2) for each active centre in ascending k.
  template <class Visitor>
  void visitActive(const Eigen::Vector3d& p_mm, Visitor&& visit) const;

  double offset_ = 0.0;
  double cutoff_ = kDefaultCutoff;
  double log_inv_cutoff_ = 0.0;  ///< ln(1/ε), +∞ for ε = 0
  bool use_grid_ = true;
  Eigen::Matrix3Xd centres_mm_;
  Eigen::VectorXd weights_;
  Eigen::VectorXd shapes_per_mm2_;
  std::vector<RadiusClass> classes_;  ///< sorted by exponent; empty when ε = 0
};

}  // namespace rbfmuscle
