// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Repair of the defects segmentation leaves in a closed surface, limited to what is
/// provably safe: no vertex moves, every triangle kept is one of the input's, and what is
/// removed has no area, cancels out (back-to-back pairs: on every edge two sides of opposite
/// winding, so the surface and the inside of every point stay as they were), repeats a
/// triangle that stays, or is a detached shell enclosing at most a millionth of the volume
/// (by default). What cannot be repaired this way is left as
/// it is, for validateMesh to report.
///
/// The steps, in order:
/// 1. Collapsed triangles (a vertex index repeated, as when two coincident vertices were
///    merged) are removed: they have no area, and their sides cancel along their edges.
/// 2. Triangles on the same three vertices are reduced: a back-to-back pair (opposite
///    winding) cancels and both go; of several wound the same way, one stays. A pair covers no
///    volume and its two sides on each edge cancel, so the surface is unchanged. When every
///    triangle would go (a surface and its reverse on top of each other), the mesh is left as
///    it is after step 1 and steps 3 and 4 are skipped.
/// 3. Pinches are split: at an edge shared by 2k triangles (k wound each way) the sides are
///    paired so that each pair bounds one sheet, found by walking round an end vertex of the
///    edge from each side until the walk comes back to the edge. Then every vertex whose
///    triangles form several fans (triangles joined across paired edges round it) gets one
///    copy per further fan, at the same position. Only the connectivity changes.
///    Done only when every edge can be paired; otherwise nothing is split.
/// 4. Closed shells that a split detaches and that enclose at most
///    `max_detached_shell_volume_fraction` of the mesh's volume (in absolute value) are
///    removed: a flat pocket or sliver of the segmentation hanging off the surface at a pinch.
///    The largest shell is never removed.
/// Vertices that no remaining triangle uses are then dropped (the others keep their order).
#include <string>

#include "geometry/triangle_mesh.h"

namespace rbfmuscle {

/// Limits of repairMesh.
struct MeshRepairOptions {
  /// A shell detached by splitting a pinch is removed when |its volume| ≤ this fraction
  /// of |the mesh's volume| (dimensionless).
  double max_detached_shell_volume_fraction = 1e-6;
};

/// What repairMesh found and did. All counts are 0 for a mesh it left untouched.
struct MeshRepairReport {
  int collapsed_triangles = 0;    ///< removed: a vertex index repeated (step 1).
  int back_to_back_pairs = 0;     ///< pairs removed: same vertices, opposite winding (step 2).
  int duplicate_triangles = 0;    ///< extra copies removed: same vertices, same winding (step 2).
  /// Edges shared by more than two triangles once collapsed triangles are removed.
  int non_manifold_edges = 0;
  /// Vertices on no non-manifold edge whose triangles form several fans (two sheets touching at a
  /// point), after step 2.
  int pinched_vertices = 0;
  int unsplit_edges = 0;          ///< non-manifold edges left because they could not be paired.
  bool cancels_out = false;       ///< every triangle has a back-to-back twin: left unreduced.
  int vertex_copies = 0;          ///< vertex copies made by splitting and still used.
  int removed_shells = 0;         ///< detached shells removed (step 4).
  int removed_shell_triangles = 0;      ///< triangles of those shells.
  double removed_shell_volume_mm3 = 0;  ///< sum of their signed volumes (mm³).
  int dropped_vertices = 0;       ///< vertices used before the repair and by no triangle after.
  double volume_before_mm3 = 0;   ///< signed volume before (calcVolume, mm³).
  double volume_after_mm3 = 0;    ///< signed volume after (mm³).

  /// True when the mesh was changed.
  bool changedMesh() const;
  /// True when some defect was left unrepaired (an edge that could not be split, or a mesh
  /// that cancels out).
  bool leftDefects() const { return unsplit_edges > 0 || cancels_out; }
  /// True when there was something to repair (changed, or a defect left).
  bool foundDefects() const { return changedMesh() || leftDefects(); }
  /// One clause for a warning, e.g. "3 non-manifold edges and 1 pinched vertex repaired: removed
  /// 4 collapsed triangles, ...; volume 103495.7 mm³ before, 103495.7 mm³ after"; empty when
  /// nothing was found.
  std::string describe() const;
};

/// Repairs `mesh` in place as the file comment describes. Leaves `mesh` bit-identical when it
/// has none of those defects. O(T log T).
MeshRepairReport repairMesh(TriangleMesh& mesh, const MeshRepairOptions& options = {});

}  // namespace rbfmuscle
