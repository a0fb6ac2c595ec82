#pragma once
/// @file
/// Probe points on a muscle's implicit surface f = 0: picked from a rest surface mesh,
/// pulled back onto the current surface by Newton steps, and the local muscle thickness
/// at each (issue 5, contact_resolver.h).
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
/// @return true when the tolerance was reached (false: step cap or a vanishing gradient).
bool projectOntoSurface(const GaussianField& field, Eigen::Vector3d& x_mm, int max_steps, double step_cap_mm,
                        double tolerance_mm);

/// Local muscle thickness (mm) at a surface point p (f(p) ≈ 0): the distance from p along
/// the inward normal u = ∇f/‖∇f‖ to the first point where f becomes ≤ 0 again, found by
/// marching in steps of `step_mm` and bisecting the last step; `max_mm` when f stays
/// positive that far (or ∇f vanishes at p).
/// @throws std::invalid_argument if step_mm ≤ 0 or max_mm < step_mm.
double calcLocalThickness(const GaussianField& field, const Eigen::Vector3d& p_mm, double step_mm, double max_mm);

}  // namespace rbfmuscle
