#pragma once
/// @file
/// Probe points on a muscle's implicit surface f = 0: picked from a rest surface mesh,
/// pulled back onto the current surface by Newton steps, and the local muscle thickness
/// at each (issue 5, contact_resolver.h).
#include <cmath>
#include <vector>

#include <Eigen/Core>

#include "geometry/triangle_mesh.h"
#include "rbf/gaussian_field.h"

namespace rbfmuscle {

/// About `count` vertices of `surface` spread evenly over it (mm, the surface's frame):
/// one vertex per occupied cell of a cubic grid (the vertex nearest the cell centre), the
/// cell edge h found by bisection on log h so the number of occupied cells is the largest
/// ≤ `count` reached within 30 bisection steps. Deterministic; the result keeps vertex order.
/// All vertices when the mesh has ≤ `count`.
/// @throws std::invalid_argument if count < 1 or the mesh has no vertex.
Eigen::Matrix3Xd sampleSurfaceProbes(const TriangleMesh& surface, int count);

/// f(x) and ∇f(x) (GaussianField formulas) from one pass over the centres active at x.
double calcValueAndGradient(const GaussianField& field, const Eigen::Vector3d& x_mm, Eigen::Vector3d& gradient);

/// Newton projection of one point onto {f = 0} along the gradient:
/// x ← x − f(x) ∇f(x)/‖∇f(x)‖², each step shortened to at most `step_cap_mm`, at most
/// `max_steps` steps, stopping once |f|/‖∇f‖ ≤ `tolerance_mm` (first-order distance to the
/// surface). The total move is therefore ≤ max_steps · step_cap_mm.
/// `gradient`, when given, gets ∇f at the returned point (the last evaluation).
/// @return true when the tolerance was reached (false: step cap or a vanishing gradient).
bool projectOntoSurface(const GaussianField& field, Eigen::Vector3d& x_mm, int max_steps, double step_cap_mm,
                        double tolerance_mm, Eigen::Vector3d* gradient = nullptr);

/// projectOntoSurface with f(x) and ∇f(x) from `evaluate(x, gradient) → f` (same steps, same
/// stops; the same result when `evaluate` gives calcValueAndGradient's numbers).
template <class Evaluate>
bool projectOntoSurfaceWith(Evaluate&& evaluate, Eigen::Vector3d& x_mm, int max_steps, double step_cap_mm,
                            double tolerance_mm, Eigen::Vector3d* gradient = nullptr) {
  for (int step = 0; step <= max_steps; ++step) {
    Eigen::Vector3d g;
    const double f = evaluate(x_mm, g);
    if (gradient) *gradient = g;
    const double g2 = g.squaredNorm();
    if (!(g2 > 1e-24)) return false;
    const double distance = std::abs(f) / std::sqrt(g2);
    if (distance <= tolerance_mm) return true;
    if (step == max_steps) return false;
    Eigen::Vector3d move = -(f / g2) * g;
    const double length = move.norm();
    if (length > step_cap_mm) move *= step_cap_mm / length;
    x_mm += move;
  }
  return false;
}

/// f and ∇f of `field` at points near a group of probes, from the centres that can be active
/// there (collected once per group) instead of a grid search per evaluation. Bitwise the
/// numbers of calcValueAndGradient: the same cut-off test α r² ≤ ln(1/ε) on the same doubles,
/// the centres summed in ascending index order.
class LocalFieldEvaluator {
 public:
  /// Collects the centres k with ‖c − ξ_k‖ ≤ r_k + radius_mm (r_k the cut-off radius), i.e.
  /// every centre that can be active within radius_mm of c; from `among` (ascending indices,
  /// e.g. another evaluator's candidates for a ball holding this one) when given, else from all.
  void collect(const GaussianField& field, const Eigen::VectorXd& cutoff_radius_mm, const Eigen::Vector3d& c_mm,
               double radius_mm, const std::vector<int>* among = nullptr);
  /// The collected centres (ascending indices).
  const std::vector<int>& getCandidates() const { return candidates_; }
  /// f(x) and ∇f(x) for ‖x − c‖ ≤ radius_mm of the last collect (exact there), of the field as
  /// it was then (the candidates' centres, shapes and weights are copied, contiguous).
  double operator()(const Eigen::Vector3d& x_mm, Eigen::Vector3d& gradient) const;
  /// Number of collected centres.
  int size() const { return static_cast<int>(candidates_.size()); }

 private:
  double offset_ = 0.0;
  double log_inv_cutoff_ = 0.0;
  std::vector<int> candidates_;  ///< ascending
  /// Per candidate, in candidates_ order: ξ (mm), α (mm⁻²), λ — contiguous for the sums.
  struct Centre {
    double x, y, z, alpha, lambda;
  };
  std::vector<Centre> centres_;
};

/// Distance (mm) from `start_mm` along the unit `direction` to the first point where f ≤ 0:
/// marched in steps of `step_mm`, the last step bisected (20 halvings); `max_mm` when f stays
/// positive that far. A start with f ≤ 0 gives the first step's bisection, near 0.
/// @throws std::invalid_argument if step_mm ≤ 0 or max_mm < step_mm.
double marchToSurface(const GaussianField& field, const Eigen::Vector3d& start_mm, const Eigen::Vector3d& direction,
                      double step_mm, double max_mm);

/// Local muscle thickness (mm) at a surface point p (f(p) ≈ 0): the distance from p along
/// the inward normal u = ∇f/‖∇f‖ to the first point where f becomes ≤ 0 again, found by
/// marching in steps of `step_mm` and bisecting the last step; `max_mm` when f stays
/// positive that far (or ∇f vanishes at p).
/// @throws std::invalid_argument if step_mm ≤ 0 or max_mm < step_mm.
double calcLocalThickness(const GaussianField& field, const Eigen::Vector3d& p_mm, double step_mm, double max_mm);

}  // namespace rbfmuscle
