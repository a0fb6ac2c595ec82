// SPDX-License-Identifier: Apache-2.0
#include "pipeline/surface_stage.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rbfmuscle {

SurfaceStage::SurfaceStage(std::shared_ptr<TissueLattice> lattice, TriangleMesh rest_surface_M,
                           const DeformedField& rest_field, const SurfaceSettings& settings)
    : lattice_(std::move(lattice)), rest_(std::move(rest_surface_M)), settings_(settings) {
  if (settings.newton_steps < 1 || !(settings.tolerance > 0.0) || !(settings.max_step_mm > 0.0))
    throw std::invalid_argument("SurfaceSettings: need newton_steps >= 1, tolerance > 0, max_step_mm > 0");
  binding_ = lattice_->bind(rest_.vertices_mm);
  lists_ = findMaterialNeighbours(rest_field, rest_.vertices_mm);
}

void SurfaceStage::run(MuscleState& state, const FrameInput&) {
  TriangleMesh& surface = state.surface_M;
  surface.triangles = rest_.triangles;
  lattice_->carry(binding_, surface.vertices_mm);
  double residual = 0.0, depth = 0.0;
  for (Eigen::Index v = 0; v < surface.vertices_mm.cols(); ++v) {
    const MuscleShape shape(state, lists_.begin(static_cast<int>(v)), lists_.count(static_cast<int>(v)));
    Eigen::Vector3d p = surface.vertices_mm.col(v);
    FieldSample g = shape.calcSample(p);
    for (int step = 0; step < settings_.newton_steps && std::abs(g.value) > settings_.tolerance; ++step) {
      const double n2 = g.gradient.squaredNorm();
      if (!(n2 > 1e-24)) break;
      Eigen::Vector3d delta = -g.value * g.gradient / n2;
      const double length = delta.norm();
      if (length > settings_.max_step_mm) delta *= settings_.max_step_mm / length;
      p += delta;
      g = shape.calcSample(p);
    }
    surface.vertices_mm.col(v) = p;
    residual = std::max(residual, std::abs(g.value));
    if (state.bones) depth = std::max(depth, -state.bones->sample(p).value_mm);
  }
  report_ = Report{residual, state.bones ? depth : kNaN};
}

}  // namespace rbfmuscle
