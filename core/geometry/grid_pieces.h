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

/// The lattice coordinates (i, j, k) of node v = i + n₀(j + n₁k) of an n₀×n₁×n₂ grid.
inline std::array<std::int64_t, 3> splitNodeIndex(std::int64_t v, const std::array<std::int64_t, 3>& n) {
  return {v % n[0], (v / n[0]) % n[1], v / (n[0] * n[1])};
}

/// Calls visit(u) for each node u joined to node v = i + n₀(j + n₁k) by an edge labelGridPieces
/// joins along (14 at most); stops and returns true when a call returns true.
template <class Visit>
bool visitJoinedNodes(std::int64_t v, const std::array<std::int64_t, 3>& n, Visit&& visit) {
  const auto [i, j, k] = splitNodeIndex(v, n);
  for (int mask = 1; mask < 8; ++mask)
    for (int sign : {1, -1}) {
      const std::int64_t a = i + sign * (mask & 1), b = j + sign * ((mask >> 1) & 1), c = k + sign * ((mask >> 2) & 1);
      if (a >= 0 && b >= 0 && c >= 0 && a < n[0] && b < n[1] && c < n[2] && visit(a + n[0] * (b + n[1] * c))) return true;
    }
  return false;
}

/// The nodes of `set` that a path through `set` joins to the grid's boundary (flags per node).
std::vector<char> findReachedFromBoundary(const std::vector<char>& set, const std::array<std::int64_t, 3>& n);

}  // namespace rbfmuscle
