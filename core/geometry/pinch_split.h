// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Internal to rbfmuscle_geometry: step 3 of repairMesh, splitting pinched edges and
/// vertices by giving each sheet its own copy of the vertex.
#include <vector>

#include "geometry/triangle_mesh.h"

namespace rbfmuscle::detail {

/// What splitPinches found and did.
struct PinchSplit {
  int non_manifold_edges = 0;  ///< edges with more than two triangle sides.
  int unsplit_edges = 0;       ///< of those, left as they were (nothing is split then).
  int pinched_vertices = 0;    ///< vertices on no non-manifold edge with several fans.
  int vertex_copies = 0;       ///< copies appended to `vertices_mm`.
  /// Per vertex of the split mesh: 1 when it was split (the original and its copies).
  std::vector<char> at_pinch;
  /// Original vertex of each copy: copy i is vertex V + i of the split mesh.
  std::vector<int> copy_of;
};

/// Pairs the sides of each edge (an edge used by exactly two triangles in opposite directions
/// pairs them; a non-manifold edge with k sides each way is paired by walking round an end
/// vertex from each side that leaves it until the walk returns to the edge), groups the
/// triangles round each vertex into fans joined across paired edges, and gives every fan after
/// the first a copy of the vertex (same position, appended). When some edge cannot be paired
/// (open, inconsistently wound, or a non-manifold edge whose walks do not pair its sides) the
/// mesh is left unchanged. Expects no collapsed triangles. Every walk is capped at T steps.
PinchSplit splitPinches(TriangleMesh& mesh);

}  // namespace rbfmuscle::detail
