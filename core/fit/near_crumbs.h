// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Bumps of a fitted field that a small rise would turn into islands of its surface, and dips
/// that a small fall would turn into bubbles inside it.
#include <Eigen/Geometry>

#include "rbf/gaussian_field.h"

namespace rbfmuscle {

/// Levels of findNearCrumbs on either side of f = 0: margin·2⁻ⁱ for i < this, and 0.
constexpr int kNearCrumbLevels = 5;

/// The peaks of f's bumps that lie apart from the surface but come within `margin` of it, and
/// the floors of its dips that lie inside but come within `margin` of it: for each level ε
/// (ε = margin·2⁻ⁱ, i < kNearCrumbLevels, and ε = 0), the highest node of every piece of
/// {f > −ε} but the largest, and the lowest node of every piece of {f < ε} apart from the
/// outside (the pieces joined to where {f < −1} reaches the grid's boundary; with no such
/// place, the largest), on the grid of `cell_mm` over `box_mm` that extractIsoSurface samples
/// (pieces joined as labelGridPieces joins them). Each node once, the nearest f = 0 first. A motion that moves f
/// by less than the margin where a bump or a dip lies cannot make it an island or a bubble; a
/// node found at several levels is the same node.
/// @throws std::invalid_argument if margin < 0, cell_mm ≤ 0 or the grid exceeds 10⁹ nodes.
Eigen::Matrix3Xd findNearCrumbs(const GaussianField& field, const Eigen::AlignedBox3d& box_mm, double cell_mm,
                                double margin);

}  // namespace rbfmuscle
