// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Kernels near each point of a set that moves with the tissue, found once at rest.
///
/// Why lists fixed at rest: a point carried by the tissue map keeps its place among the
/// kernels, which the same map carries and stretches, so the kernels that reach it now are
/// those that reached it at rest, up to the map's curvature across a kernel. A frame then
/// evaluates the field at its carried points without any search. The lists are grown by a
/// scale on the cut-off radius and a margin, which bound how far from the affine picture a
/// point may drift (after a projection onto the surface, say) and still see every kernel.
#include "rbf/deformed_field.h"

#include <Eigen/Core>

#include <vector>

namespace rbfmuscle {

/// CSR lists: the kernels of point j are kernels[start[j] .. start[j+1]), ascending.
struct NeighbourLists {
  std::vector<int> start{0};  ///< P + 1 offsets
  std::vector<int> kernels;   ///< kernel indices
  /// Number of points P.
  int size() const { return static_cast<int>(start.size()) - 1; }
  /// First kernel index of point j.
  const int* begin(int j) const { return kernels.data() + start[static_cast<size_t>(j)]; }
  /// Number of kernels of point j.
  int count(int j) const { return start[static_cast<size_t>(j) + 1] - start[static_cast<size_t>(j)]; }
};

/// For each rest point x (3×P, mm), the kernels k of `field` (its current kernels, taken as
/// rest: F = I is assumed) with ‖x − ξₖ‖ ≤ radius_scale · rₖ + margin_mm, where
/// rₖ = √(ln(1/ε)/αₖ) is the cut-off radius.
/// @throws std::invalid_argument if radius_scale < 1, margin_mm < 0, or a point is not finite.
NeighbourLists findMaterialNeighbours(const DeformedField& field, const Eigen::Matrix3Xd& rest_points_mm,
                                      double radius_scale = 1.25, double margin_mm = 2.0);

}  // namespace rbfmuscle
