// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Internal to rbfmuscle_geometry: the undirected edge table of a triangle mesh, shared by
/// the checks, the orientation repair and the edge pseudo-normals of MeshDistance.
#include <array>
#include <vector>

#include "geometry/triangle_mesh.h"

namespace rbfmuscle::detail {

/// Undirected edges. Edge c of triangle t joins corners c and (c+1) mod 3 and is
/// `of_triangle(c, t)`; each edge knows its (lo, hi) vertices, how many triangle sides use
/// it and how many of those run lo → hi.
struct EdgeTable {
  std::vector<std::array<int, 2>> vertices;  ///< (lo, hi) vertex indices, lo ≤ hi.
  std::vector<int> use_count;                ///< triangle sides on the edge.
  std::vector<int> forward_count;            ///< sides directed lo → hi.
  Eigen::Matrix3Xi of_triangle;              ///< 3×T edge ids.

  /// Edge used by exactly two sides in opposite directions.
  bool isConsistentManifold(int e) const { return use_count[e] == 2 && forward_count[e] == 1; }
};

/// Builds the table in O(T log T) by sorting the 3T sides.
EdgeTable buildEdgeTable(const TriangleMesh& mesh);

}  // namespace rbfmuscle::detail
