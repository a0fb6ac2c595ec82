// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Moving a mesh out of solids it overlaps: the repair for two segmentations that overlap
/// (a muscle lying inside its bone at rest), which no motion of the bones can undo.
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "geometry/mesh_distance.h"
#include "geometry/triangle_mesh.h"

namespace rbfmuscle {

/// A closed solid, with where it lies in the moved mesh's frame.
struct PlacedSolid {
  const MeshDistance* distance = nullptr;  ///< signed distance queries, in the solid's own frame
  Eigen::Isometry3d X_mesh_solid = Eigen::Isometry3d::Identity();  ///< solid frame → mesh frame
  std::string name;                        ///< for reports (a file name)
};

/// How far a mesh may overlap a solid, and how a move fades over the mesh.
struct MoveOutSettings {
  /// Vertices up to this deep in a solid stay (mm): the penetration the contact checks allow.
  double tolerance_mm = 0.5;
  /// A moved vertex lands this far outside the face (mm), so that a fit of the moved mesh,
  /// off by a few tenths of a millimetre, does not sink it again.
  double clearance_mm = 0.3;
  /// The move fades to zero over the mesh's vertices within this distance (mm) of a moved one,
  /// so the tissue around an overlap moves with it and keeps its thickness.
  double fade_mm = 20.0;
  /// Rounds of moving (each one from the solids' faces again) before giving up.
  int max_rounds = 5;
};

/// What moveOutOfSolids did.
struct MoveOutReport {
  int vertices_inside = 0;     ///< vertices deeper than the tolerance, before the move
  double depth_max_mm = 0;     ///< deepest of them (mm)
  std::string deepest_solid;   ///< the solid holding the deepest one
  int vertices_moved = 0;      ///< vertices that moved by more than 1 µm
  double move_max_mm = 0;      ///< largest move (mm)
  int rounds = 0;              ///< rounds run
  int vertices_left = 0;       ///< vertices still deeper than the tolerance (0 unless the cap stopped it)
  std::string stop;            ///< "none inside" or "round cap"
};

/// Moves every vertex of `mesh` deeper than `settings.tolerance_mm` inside a solid onto that
/// solid's nearest face (`settings.clearance_mm` outside it), and the vertices around them smoothly with them: the move is the
/// harmonic extension (uniform Laplacian over the mesh's edges) of the face moves to zero at
/// the vertices farther than `settings.fade_mm` from every one of them. Repeats from the faces
/// until no vertex is deeper than the tolerance, at most `settings.max_rounds` times. A mesh
/// that overlaps nothing is returned bitwise unchanged.
/// @throws std::invalid_argument for a null solid or bad settings.
MoveOutReport moveOutOfSolids(TriangleMesh& mesh, const std::vector<PlacedSolid>& solids,
                              const MoveOutSettings& settings = {});

/// One sentence for a warning: how deep `mesh_path` lay in the solids and how it was moved
/// out (with `settings`' tolerance and fade); "" when nothing lay deeper than the tolerance.
std::string describeMoveOut(const std::string& mesh_path, const MoveOutReport& report,
                            const MoveOutSettings& settings = {});

}  // namespace rbfmuscle
