// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// The pieces of a set of grid nodes, joined as the extracted surface joins them.
#include <array>
#include <cstdint>
#include <vector>

namespace rbfmuscle {

/// The pieces of the nodes marked inside, each node's piece and each piece's size.
struct GridPieces {
  std::vector<int> piece_of_node;         ///< per node: its piece, or −1 when not inside
  std::vector<std::int64_t> nodes_of_piece;  ///< per piece: its nodes; pieces in order of their first node
  int findLargest() const;                ///< the piece with the most nodes (the first of equals); −1 when none
};

/// Labels the pieces of the nodes with inside[i + n₀(j + n₁k)] ≠ 0 on an n₀×n₁×n₂ grid. Two
/// nodes inside are joined when an edge of the grid's tetrahedra (iso_surface.h) joins them:
/// the three axes, the three face diagonals and the cube diagonal towards +. So the pieces are
/// those the extracted surface bounds.
/// @throws std::invalid_argument if inside does not hold n₀n₁n₂ flags or the grid has ≥ 2³¹ nodes.
GridPieces labelGridPieces(const std::vector<char>& inside, const std::array<std::int64_t, 3>& n);

}  // namespace rbfmuscle
