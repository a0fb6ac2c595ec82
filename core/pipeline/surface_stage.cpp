// SPDX-License-Identifier: Apache-2.0
#include "pipeline/surface_stage.h"

#include "geometry/mesh_measures.h"

#include <algorithm>
#include <cmath>

namespace rbfmuscle {

SurfaceStage::SurfaceStage(std::shared_ptr<TissueLattice> lattice, TriangleMesh rest_surface_M,
                           const DeformedField& rest_field, const SurfaceSettings& settings)
    : lattice_(std::move(lattice)), rest_(std::move(rest_surface_M)), settings_(settings) {
  checkSurfaceSettings(settings);
  binding_ = lattice_->bind(rest_.vertices_mm);
  lists_ = findMaterialNeighbours(rest_field, rest_.vertices_mm);
}

void SurfaceStage::run(MuscleState& state, const FrameInput&) {
  TriangleMesh& surface = state.surface_M;
  surface.triangles = rest_.triangles;
  lattice_->carry(binding_, surface.vertices_mm);
  double residual = 0.0, depth = 0.0, start = 0.0;
  int unresolved = 0;
  found_.assign(static_cast<size_t>(surface.vertices_mm.cols()), 1);
  calcVertexNormals(surface, normals_);
  for (Eigen::Index v = 0; v < surface.vertices_mm.cols(); ++v) {
    const int j = static_cast<int>(v);
    Eigen::Vector3d p = surface.vertices_mm.col(v);
    // First onto the field's surface f = 0 (smooth), then, where that lies in a bone, onto the
    // bone's face on the muscle's side: the surface of min(f, s) is f = 0 outside the bones and
    // s = 0 on them.
    const MuscleShape field(state, lists_.begin(j), lists_.count(j), BoneContact::kIgnored);
    double start_value = 0.0;
    const FieldSample on_field = projectVertex(field, normals_.col(v), p, settings_, start_value);
    start = std::max(start, std::abs(start_value));
    // min(f, s): the tracked surface does not show tissue folded out of a bone (tissue_fold.h).
    const MuscleShape shape(state, lists_.begin(j), lists_.count(j), BoneContact::kCut);
    if (state.bones) exitBoneIntoMuscle(field, on_field.gradient, *state.bones, p, settings_);
    const double g = shape.calcValue(p);
    surface.vertices_mm.col(v) = p;
    if (std::abs(g) > settings_.tolerance) {  // the muscle there lies wholly in a bone: no surface left
      ++unresolved;
      residual = std::max(residual, std::abs(g));
      found_[static_cast<size_t>(v)] = 0;
      continue;
    }
    if (state.bones) depth = std::max(depth, -state.bones->calcValue(p));
  }
  if (unresolved > 0) {  // triangles at vertices that found no surface are not part of it
    Eigen::Index kept = 0;
    for (Eigen::Index t = 0; t < surface.triangles.cols(); ++t)
      if (found_[static_cast<size_t>(surface.triangles(0, t))] && found_[static_cast<size_t>(surface.triangles(1, t))] &&
          found_[static_cast<size_t>(surface.triangles(2, t))])
        surface.triangles.col(kept++) = surface.triangles.col(t);
    surface.triangles.conservativeResize(3, kept);
  }
  report_ = Report{residual, static_cast<double>(unresolved), state.bones ? depth : kNaN, start};
}

}  // namespace rbfmuscle
