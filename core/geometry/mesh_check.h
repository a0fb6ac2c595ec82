// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Checks that a triangle mesh bounds a solid (closed, manifold, consistently and outward
/// wound, finite, no degenerate triangles), error messages that say what is wrong, and a
/// repair of the winding.
#include <string>
#include <vector>

#include "geometry/mesh_error.h"
#include "geometry/triangle_mesh.h"

namespace rbfmuscle {

/// What checkMesh found. Every count is 0 for a mesh that bounds a solid.
struct MeshReport {
  int vertex_count = 0;            ///< V.
  int triangle_count = 0;          ///< T.
  int non_finite_vertices = 0;     ///< vertices with a NaN or infinite coordinate.
  /// Triangles with a repeated vertex index or zero area:
  /// ‖(b − a) × (c − a)‖ ≤ 1e-12 · (longest edge)², i.e. all three corners on one line.
  int degenerate_triangles = 0;
  int boundary_edges = 0;          ///< edges used by one triangle (open boundary).
  int non_manifold_edges = 0;      ///< edges used by three or more triangles.
  int inconsistent_edges = 0;      ///< edges used by two triangles in the same direction.
  int components = 0;              ///< connected pieces (triangles sharing a vertex).
  double signed_volume_mm3 = 0.0;  ///< calcVolume (mm³); < 0 means wound inward.

  /// Closed 2-manifold: no boundary edges and no non-manifold edges.
  bool isWatertight() const { return boundary_edges == 0 && non_manifold_edges == 0; }
  /// One sentence per problem; empty when the mesh bounds a solid (including outward
  /// winding: signed volume > 0).
  std::vector<std::string> listProblems() const;
  /// Counts and problems in one readable paragraph (for logs and `info` output).
  std::string describe() const;
};

/// Counts every problem listed in MeshReport. O(T log T).
MeshReport checkMesh(const TriangleMesh& mesh);

/// Throws MeshError "<source_name>: <problem>; <problem>..." when checkMesh finds any
/// problem, e.g. "iliacus.ply: 12 boundary edges — the mesh is not watertight (open
/// boundary)". Returns quietly for a closed, manifold, outward-wound, finite mesh.
void validateMesh(const TriangleMesh& mesh, const std::string& source_name);

/// Makes the winding consistent and outward: per connected piece (triangles joined across
/// edges used by exactly two triangles), a breadth-first walk flips each triangle to agree
/// with its neighbour, then the whole piece is flipped if its signed volume is negative.
/// A flip swaps corners 1 and 2. Non-orientable pieces keep the first winding reached.
/// @return number of triangles flipped.
int orientConsistently(TriangleMesh& mesh);

}  // namespace rbfmuscle
