// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// One Gaussian's contribution to the field and its derivatives, as inline
/// functions shared by every summation (GaussianField, CurvatureCost, and
/// callers building sparse matrices), so that all of them produce bitwise the
/// same numbers for the same centre.
///
/// Notation (d = 3): one centre ξ with weight λ and shape α (mm⁻²), evaluated
/// at x; d = x − ξ (mm), r² = ‖d‖² (mm²), φ = exp(−α r²).
#include <Eigen/Core>

#include <cmath>

namespace rbfmuscle::gaussian {

/// φ = exp(−α r²) for shape α (mm⁻²) and squared distance r² (mm²).
inline double calcPhi(double alpha_per_mm2, double r2_mm2) {
  return std::exp(-alpha_per_mm2 * r2_mm2);
}

/// Cut-off radius r_c = √(ln(1/ε)/α) (mm) beyond which φ < ε; +∞ for ε = 0.
inline double calcCutoffRadius(double alpha_per_mm2, double cutoff) {
  return std::sqrt(-std::log(cutoff) / alpha_per_mm2);
}

/// Contribution to the mean curvature κ = tr(H f)/3:
/// (2/3) α λ φ (2α r² − 3)  (field unit / mm²).
inline double calcMeanCurvatureTerm(double alpha, double lambda, double phi, double r2) {
  return (2.0 / 3.0) * alpha * lambda * phi * (2.0 * alpha * r2 - 3.0);
}

/// ∂κ/∂λ for this centre: (2/3) α φ (2α r² − 3)  (mm⁻²).
inline double calcMeanCurvatureDerivativeWrtWeight(double alpha, double phi, double r2) {
  return (2.0 / 3.0) * alpha * phi * (2.0 * alpha * r2 - 3.0);
}

/// ∂κ/∂ξ for this centre: (4/3) α² λ φ (2α r² − 5) d  (field unit / mm³).
/// The gradient of κ with respect to x is minus the sum of these over centres.
inline Eigen::Vector3d calcMeanCurvatureDerivativeWrtCentre(double alpha, double lambda,
                                                            double phi,
                                                            const Eigen::Vector3d& d, double r2) {
  return ((4.0 / 3.0) * alpha * alpha * lambda * phi * (2.0 * alpha * r2 - 5.0)) * d;
}

/// ∂f/∂ξ for this centre: 2 α λ φ d  (field unit / mm); ∇f is minus the sum
/// of these over centres.
inline Eigen::Vector3d calcValueDerivativeWrtCentre(double alpha, double lambda, double phi,
                                                    const Eigen::Vector3d& d) {
  return (2.0 * alpha * lambda * phi) * d;
}

}  // namespace rbfmuscle::gaussian
