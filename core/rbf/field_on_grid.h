#pragma once
/// @file
/// A Gaussian field on every node of a regular grid, by separable sums.
#include "rbf/gaussian_field.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace rbfmuscle {

/// Nodes origin + cell·(i, j, k), 0 ≤ i < counts[0], 0 ≤ j < counts[1], 0 ≤ k < counts[2];
/// node (i, j, k) is number i + counts[0]·(j + counts[1]·k).
struct RegularGrid {
  Eigen::Vector3d origin_mm = Eigen::Vector3d::Zero();  ///< node (0, 0, 0) (mm)
  double cell_mm = 1.0;                                 ///< spacing (mm), > 0
  std::array<std::int64_t, 3> counts{{0, 0, 0}};        ///< nodes per axis, ≥ 0
  /// Number of nodes.
  std::int64_t size() const { return counts[0] * counts[1] * counts[2]; }
  /// Number of node (i, j, k).
  std::int64_t index(std::int64_t i, std::int64_t j, std::int64_t k) const { return i + counts[0] * (j + counts[1] * k); }
  /// Position of node `id` (mm).
  Eigen::Vector3d node(std::int64_t id) const {
    return origin_mm + cell_mm * Eigen::Vector3d(double(id % counts[0]), double((id / counts[0]) % counts[1]),
                                                 double(id / (counts[0] * counts[1])));
  }
};

/// f = b + Σ λₖ φₖ at every node of `grid` into `values` (resized to grid.size()).
///
/// On a grid, φ = e^{−α dx²} e^{−α dy²} e^{−α dz²}: each centre's one-dimensional factors
/// are computed once over its cut-off range and each node costs a product and a sum per
/// centre, no exponential, so the cost follows Σₖ (nodes in centre k's cut-off sphere)
/// rather than nodes × active centres. A centre counts at a node under the field's own
/// cut-off test α r² ≤ ln(1/ε), so the values equal GaussianField::calcValue up to
/// rounding (the sums run in ascending centre order). Parallel over z layers (OpenMP),
/// results independent of the thread count.
/// @throws std::invalid_argument if cell_mm ≤ 0 or a count is negative.
void calcValuesOnGrid(const GaussianField& field, const RegularGrid& grid, std::vector<double>& values);

/// Adds Σ_{k ∈ centres} Δλₖ φₖ (the field's centre positions and shapes, Δλ = `weight_change`,
/// size N) to `values` (size grid.size()) at every node, with the cut-off test and node
/// ranges of calcValuesOnGrid: after a change of a few weights, the grid values follow at
/// the cost of those centres' cut-off spheres instead of all of them.
/// @throws std::invalid_argument as calcValuesOnGrid, or if values has the wrong size.
void addCentresOnGrid(const GaussianField& field, const RegularGrid& grid, const std::vector<int>& centres,
                      const Eigen::VectorXd& weight_change, std::vector<double>& values);

}  // namespace rbfmuscle
