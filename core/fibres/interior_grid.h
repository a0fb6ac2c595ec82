// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// The inside of a muscle field sampled on a regular grid, and shortest paths
/// through it (the routes of the fibres at rest).
#include "rbf/gaussian_field.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

namespace rbfmuscle {

/// Grid nodes with f ≥ margin, their values and 26-neighbour connectivity.
struct InteriorGrid {
  Eigen::Vector3d corner_mm = Eigen::Vector3d::Zero();  ///< position of cell (0,0,0) (mm, M)
  double spacing_mm = 0;                                ///< grid spacing h (mm)
  Eigen::Vector3i dims = Eigen::Vector3i::Zero();       ///< cells per axis
  std::vector<int> node_of_cell;  ///< node index of cell (i,j,k) at i + dims.x (j + dims.y k); −1 if outside
  Eigen::Matrix3Xd nodes_mm;      ///< positions of the interior nodes (3×n, mm, M)
  Eigen::VectorXd values;         ///< f at each node (≥ margin)
  std::vector<Eigen::Vector3i> cells;  ///< cell of each node
  /// Volume the nodes stand for, n·h³ (mm³).
  double calcVolume() const;
};

/// Samples {f ≥ margin_mm} on a regular grid of about `target_nodes` interior nodes.
/// The box is the centres' box padded by max_k 2/√αₖ, grown by half while a node on its
/// border is inside (cap 4 times); the spacing is chosen from a first coarse pass so the
/// inside holds about target_nodes nodes. Deterministic.
/// @throws std::invalid_argument if the field has no centre, target_nodes < 8, or no node is inside.
InteriorGrid makeInteriorGrid(const GaussianField& field, double margin_mm, int target_nodes);

/// The connected pieces of the grid's inside (26-neighbour edges, as findShortestPath walks):
/// the piece of each node, numbered 0 … count − 1 in the order of their first nodes.
std::vector<int> labelInteriorPieces(const InteriorGrid& grid, int& count);

/// Shortest path between nodes `from` and `to` (Dijkstra over the 26-neighbour edges):
/// edge cost ‖a − b‖ · (1 + c (1 − min(f̄, f_max)/f_max)), f̄ the mean of the two node
/// values, f_max the largest node value, c = centre_preference ≥ 0 (c > 0 prefers deep
/// routes, away from the surface). Returns the node indices from `from` to `to`.
/// @throws std::invalid_argument on bad indices or c < 0, std::runtime_error if `to`
///   cannot be reached (the inside is not connected).
std::vector<int> findShortestPath(const InteriorGrid& grid, int from, int to, double centre_preference);

}  // namespace rbfmuscle
