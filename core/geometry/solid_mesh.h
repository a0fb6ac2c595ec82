// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Loading a mesh that must bound a solid (bones, muscles before fitting): repaired where
/// safe, then checked, so callers never see a mesh that is open, non-manifold or inward wound.
#include <string>

#include "geometry/mesh_warning.h"
#include "geometry/triangle_mesh.h"

namespace rbfmuscle {

/// How loadSolidMesh treats the winding and where its warning goes.
struct SolidMeshOptions {
  /// Rewind inconsistently or inward wound triangles (orientConsistently) instead of failing.
  bool fix_winding = false;
  /// Receives the loader's warning about unused vertices and repaired defects.
  MeshWarningFn warn = printMeshWarning;
};

/// loadMesh (which repairs what it can safely and warns), then validateMesh: returns a closed,
/// manifold, outward-wound mesh (mm, as stored) or stops. With `fix_winding` the mesh is
/// rewound before the check, and repaired again when rewinding lets a pinch be split.
/// @throws MeshError "<path>: <problem>; <problem>..." naming each defect left and its count,
///         e.g. "bone.ply: 12 boundary edges — the mesh is not watertight (open boundary)",
///         followed by what the loader could not repair, if anything; or as loadMesh.
TriangleMesh loadSolidMesh(const std::string& path, const SolidMeshOptions& options = {});

}  // namespace rbfmuscle
