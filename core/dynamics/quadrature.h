// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Quadrature points of the curvature cost (and of the volume): a regular grid
/// over the band {f > −β} at rest, i.e. the muscle and a shell around it, where
/// the shape matters.
#include "rbf/gaussian_field.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace rbfmuscle {

/// How to place the quadrature points.
struct QuadratureSettings {
  int target_count = 4000;  ///< wanted number of points (the result is within ~±20 %), ≥ 8
  /// β (field unit, mm for a clamped signed distance fit): keep grid nodes with f > −β.
  /// The default keeps the inside and a shell of ~4 mm around the surface (a signed-distance
  /// fit rises by ~1 per mm across its surface, up to its clamp τ, 10 mm by default).
  double band_value = 4.0;
  int coarse_cells = 48;    ///< cells per box side of the scan that finds the band's box, ≥ 4
};

/// Quadrature points with their weights.
struct Quadrature {
  Eigen::Matrix3Xd points_mm;        ///< q (3×M, mm, frame M at rest)
  Eigen::VectorXd weights_mm3;       ///< w_q = h³ (M, mm³): the cell volume
  double cell_mm = 0.0;              ///< grid spacing h (mm)
  Eigen::AlignedBox3d box_mm;        ///< box of the grid nodes (mm)
};

/// An axis-aligned box that contains {f > −β}, proved, not sampled: with
/// c = −b − β > 0 and N centres, Σλφ > c needs some λₖφₖ > c/N, i.e. a point within
/// rₖ = √(ln(N λₖ / c)/αₖ) (capped by the cut-off radius) of a centre with λₖ > c/N;
/// the box is the union of those balls' boxes. Then a coarse grid scan
/// (`coarse_cells` per side) shrinks it to the nodes with f > −β, padded by one coarse cell.
/// @throws std::invalid_argument if c ≤ 0 (the far field is inside the band) or no centre reaches the band.
Eigen::AlignedBox3d findBandBox(const GaussianField& field, double band_value, int coarse_cells);

/// The grid over findBandBox with spacing h = (V_band / target_count)^⅓ (V_band estimated
/// from the coarse scan), keeping the nodes with f > −β, in lexicographic (z, y, x) order.
/// Deterministic. @throws std::invalid_argument for bad settings (names the field) or as findBandBox.
Quadrature makeQuadrature(const GaussianField& field, const QuadratureSettings& settings);

}  // namespace rbfmuscle
