// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Stage 6 (on demand): the muscle's surface, tracked from rest.
#include "dynamics/tissue_lattice.h"
#include "geometry/triangle_mesh.h"
#include "pipeline/frame_stage.h"
#include "pipeline/surface_projection.h"
#include "rbf/neighbour_lists.h"

#include <memory>

namespace rbfmuscle {

/// The rest surface's vertices carried by the tissue map, then put onto f = 0 (surface_projection.h:
/// a vertex inside goes out along the carried surface's normal, one outside by Newton steps along
/// the gradient) and, where that lies in a bone, out along the way into the muscle to the bone's
/// face there, if it is within twice the depth: the surface of min(f, s), for pictures and for
/// checking contacts, with no grid evaluated per frame. A vertex whose part of the muscle lies
/// wholly in a bone, or whose way into the muscle runs on through the bone, finds no surface; its
/// triangles are left out (the vertex stays, so vertices keep their index from frame to frame).
/// The tissue a bone took and folded out on its face (tissue_fold.h) has no tracked vertices: the
/// tracked surface is that of min(f, s) and stops at the face. Runs only when a frame asks for it.
class SurfaceStage final : public FrameStage {
 public:
  /// @param rest_surface_M the rest surface (M, mm), e.g. extracted once from the rest field
  SurfaceStage(std::shared_ptr<TissueLattice> lattice, TriangleMesh rest_surface_M, const DeformedField& rest_field,
               const SurfaceSettings& settings);

  /// What a frame's surface tracking did.
  struct Report {
    double residual_max = kNaN;       ///< largest |min(f, s)| at an unresolved vertex
    double unresolved = kNaN;         ///< vertices that found no surface
    double bone_depth_max_mm = kNaN;  ///< deepest resolved vertex inside a bone, sampled (mm)
    double start_residual_max = kNaN; ///< largest |f| at a carried vertex before its projection
  };
  static constexpr ReportEntry<Report> kReport[] = {
      {"surface_residual_max", "1", "largest |min(f, s)| at a tracked vertex that found no surface (0: all found it)",
       &Report::residual_max},
      {"surface_vertices_unresolved", "1",
       "tracked vertices that found no surface near them: the muscle there lies wholly in a bone",
       &Report::unresolved},
      {"surface_bone_depth_max_mm", "mm", "deepest tracked surface vertex inside a bone (its sampled distance)",
       &Report::bone_depth_max_mm},
      {"surface_start_residual_max", "1",
       "largest |f| at a carried vertex before its projection: how far the kernels' field has left the tissue map's "
       "image of the rest surface (at rest: the fit's own residual there)",
       &Report::start_residual_max},
  };

  bool isNeeded(const FrameInput& input) const override { return input.want_surface; }
  void run(MuscleState& state, const FrameInput& input) override;
  void appendReport(std::vector<double>& values) const override { appendTable(kReport, report_, values); }
  /// The rest surface.
  const TriangleMesh& getRestSurface() const { return rest_; }

 private:
  std::shared_ptr<TissueLattice> lattice_;
  TriangleMesh rest_;
  SurfaceSettings settings_;
  LatticeBinding binding_;
  NeighbourLists lists_;
  std::vector<char> found_;  ///< per vertex: whether it found the surface this frame
  Eigen::Matrix3Xd normals_; ///< the carried surface's vertex normals this frame (unnormalised)
  Report report_;
};

}  // namespace rbfmuscle
