// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Finding where a triangle mesh crosses itself: pairs of triangles that share no vertex and
/// intersect. A mesh that crosses itself has no well-defined inside, so a fit to it is poor
/// without any other sign; the fit warns (fit_pipeline.h).
///
/// Method: a uniform grid over the mesh's box (about one triangle per cell) is the broad
/// phase; each pair of triangles whose boxes overlap and that share no vertex is tested by the
/// separating-axis theorem on 17 axes (both normals, the 9 products of edges, and the 6
/// in-plane edge normals, which settle coplanar pairs). Two triangles count as intersecting
/// when no axis separates them by more than 1e-9 of the mesh's extent, so triangles that only
/// touch across a gap of round-off are counted. Pairs sharing a vertex or an edge are never
/// tested: they always touch, and a fold between neighbours shows up as another defect.
/// Own code rather than FCL, so that core/geometry needs no collision library; cost about
/// 0.1 s for 10⁵ triangles.
#include <vector>

#include "geometry/triangle_mesh.h"

namespace rbfmuscle {

/// What findSelfIntersections found.
struct SelfIntersections {
  int pairs = 0;                         ///< intersecting triangle pairs found (up to the cap)
  bool capped = false;                   ///< true when the search stopped at `max_pairs`
  std::vector<std::pair<int, int>> examples;  ///< the first few pairs (triangle indices)
};

/// Pairs of triangles of `mesh` that share no vertex and intersect; stops after `max_pairs`.
SelfIntersections findSelfIntersections(const TriangleMesh& mesh, int max_pairs = 1000);

/// Separating-axis test of triangles (a0, a1, a2) and (b0, b1, b2): true when no axis
/// separates them by more than `gap`.
bool trianglesIntersect(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& a2,
                        const Eigen::Vector3d& b0, const Eigen::Vector3d& b1, const Eigen::Vector3d& b2,
                        double gap);

}  // namespace rbfmuscle
