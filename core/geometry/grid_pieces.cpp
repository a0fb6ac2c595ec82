// SPDX-License-Identifier: Apache-2.0
#include "geometry/grid_pieces.h"

#include <limits>
#include <stdexcept>
#include <string>

#include "geometry/disjoint_sets.h"

namespace rbfmuscle {

int GridPieces::findLargest() const {
  int largest = -1;
  for (int p = 0; p < static_cast<int>(nodes_of_piece.size()); ++p)
    if (largest < 0 || nodes_of_piece[std::size_t(p)] > nodes_of_piece[std::size_t(largest)]) largest = p;
  return largest;
}

GridPieces labelGridPieces(const std::vector<char>& inside, const std::array<std::int64_t, 3>& n) {
  const std::int64_t count = n[0] * n[1] * n[2];
  if (n[0] < 1 || n[1] < 1 || n[2] < 1 || count != static_cast<std::int64_t>(inside.size()))
    throw std::invalid_argument("labelGridPieces: " + std::to_string(inside.size()) + " flags for a grid of " +
                                std::to_string(n[0]) + "×" + std::to_string(n[1]) + "×" + std::to_string(n[2]) + " nodes");
  if (count > std::numeric_limits<int>::max())
    throw std::invalid_argument("labelGridPieces: a grid of " + std::to_string(count) + " nodes; at most 2³¹ − 1");
  // Only the marked nodes enter the sets (their number m, often a tenth of the grid's or less):
  // piece_of_node first holds each marked node's index among them.
  GridPieces pieces;
  pieces.piece_of_node.assign(inside.size(), -1);
  std::vector<int> members;
  for (std::int64_t v = 0; v < count; ++v)
    if (inside[std::size_t(v)]) {
      pieces.piece_of_node[std::size_t(v)] = static_cast<int>(members.size());
      members.push_back(static_cast<int>(v));
    }
  DisjointSets sets(members.size());
  for (int m = 0; m < static_cast<int>(members.size()); ++m) {
    const auto [i, j, k] = splitNodeIndex(members[std::size_t(m)], n);
    for (int mask = 1; mask < 8; ++mask) {
      const std::int64_t a = i + (mask & 1), b = j + ((mask >> 1) & 1), c = k + ((mask >> 2) & 1);
      if (a >= n[0] || b >= n[1] || c >= n[2]) continue;
      const int other = pieces.piece_of_node[std::size_t(a + n[0] * (b + n[1] * c))];
      if (other >= 0) sets.join(m, other);
    }
  }
  std::vector<int> piece_of_root(members.size(), -1);
  for (int m = 0; m < static_cast<int>(members.size()); ++m) {
    int& piece = piece_of_root[std::size_t(sets.find(m))];
    if (piece < 0) {
      piece = static_cast<int>(pieces.nodes_of_piece.size());
      pieces.nodes_of_piece.push_back(0);
    }
    pieces.piece_of_node[std::size_t(members[std::size_t(m)])] = piece;
    ++pieces.nodes_of_piece[std::size_t(piece)];
  }
  return pieces;
}

std::vector<char> findReachedFromBoundary(const std::vector<char>& set, const std::array<std::int64_t, 3>& n) {
  std::vector<char> reached(set.size(), 0);
  std::vector<std::int64_t> todo;
  for (std::int64_t k = 0; k < n[2]; ++k)
    for (std::int64_t j = 0; j < n[1]; ++j)
      for (std::int64_t i = 0; i < n[0]; ++i) {
        const bool boundary = i == 0 || j == 0 || k == 0 || i == n[0] - 1 || j == n[1] - 1 || k == n[2] - 1;
        const std::int64_t v = i + n[0] * (j + n[1] * k);
        if (boundary && set[std::size_t(v)] && !reached[std::size_t(v)]) {
          reached[std::size_t(v)] = 1;
          todo.push_back(v);
        }
      }
  while (!todo.empty()) {
    const std::int64_t v = todo.back();
    todo.pop_back();
    visitJoinedNodes(v, n, [&](std::int64_t u) {
      if (set[std::size_t(u)] && !reached[std::size_t(u)]) {
        reached[std::size_t(u)] = 1;
        todo.push_back(u);
      }
      return false;
    });
  }
  return reached;
}

}  // namespace rbfmuscle
