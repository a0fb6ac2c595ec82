// SPDX-License-Identifier: Apache-2.0
/// Pieces of grid nodes are joined along the edges of the grid's tetrahedra: the axes, the face
/// diagonals and the cube diagonal towards +, so the count is the extracted surface's.
#include <gtest/gtest.h>

#include <stdexcept>

#include "geometry/grid_pieces.h"

namespace rbfmuscle {
namespace {

/// A 4×4×4 grid with the given nodes inside.
std::vector<char> makeGrid(std::initializer_list<std::array<int, 3>> nodes) {
  std::vector<char> inside(64, 0);
  for (const auto& n : nodes) inside[std::size_t(n[0] + 4 * (n[1] + 4 * n[2]))] = 1;
  return inside;
}

const std::array<std::int64_t, 3> kFour = {4, 4, 4};

TEST(GridPieces, SeparateNodesArePiecesAndTheLargestIsFound) {
  const GridPieces pieces = labelGridPieces(makeGrid({{0, 0, 0}, {3, 3, 3}, {3, 2, 3}, {0, 3, 0}}), kFour);
  ASSERT_EQ(pieces.nodes_of_piece.size(), 3u);
  EXPECT_EQ(pieces.nodes_of_piece[std::size_t(pieces.findLargest())], 2);
  EXPECT_EQ(pieces.piece_of_node[1], -1);
  EXPECT_EQ(pieces.piece_of_node[std::size_t(3 + 4 * (3 + 4 * 3))], pieces.piece_of_node[std::size_t(3 + 4 * (2 + 4 * 3))]);
}

TEST(GridPieces, TheTetrahedraJoinTheCubeDiagonalTowardsPlusButNotTheOther) {
  EXPECT_EQ(labelGridPieces(makeGrid({{1, 1, 1}, {2, 2, 2}}), kFour).nodes_of_piece.size(), 1u);
  EXPECT_EQ(labelGridPieces(makeGrid({{1, 1, 1}, {2, 2, 1}}), kFour).nodes_of_piece.size(), 1u);  // a face diagonal
  EXPECT_EQ(labelGridPieces(makeGrid({{1, 2, 1}, {2, 1, 2}}), kFour).nodes_of_piece.size(), 2u);  // another cube diagonal
  EXPECT_EQ(labelGridPieces(makeGrid({{1, 2, 1}, {2, 1, 1}}), kFour).nodes_of_piece.size(), 2u);  // the other face diagonal
}

TEST(GridPieces, AnEmptyGridHasNoPieceAndAWrongSizeIsRefused) {
  const GridPieces none = labelGridPieces(makeGrid({}), kFour);
  EXPECT_TRUE(none.nodes_of_piece.empty());
  EXPECT_EQ(none.findLargest(), -1);
  EXPECT_THROW(labelGridPieces(std::vector<char>(63, 0), kFour), std::invalid_argument);
}

}  // namespace
}  // namespace rbfmuscle
