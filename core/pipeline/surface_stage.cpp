// SPDX-License-Identifier: Apache-2.0
#include "pipeline/surface_stage.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rbfmuscle {

SurfaceStage::SurfaceStage(std::shared_ptr<TissueLattice> lattice, TriangleMesh rest_surface_M,
                           const DeformedField& rest_field, const SurfaceSettings& settings)
    : lattice_(std::move(lattice)), rest_(std::move(rest_surface_M)), settings_(settings) {
  if (settings.newton_steps < 1 || settings.max_exit_steps < 1 || !(settings.tolerance > 0.0) || !(settings.max_step_mm > 0.0))
    throw std::invalid_argument("SurfaceSettings: need newton_steps >= 1, max_exit_steps >= 1, tolerance > 0, max_step_mm > 0");
  binding_ = lattice_->bind(rest_.vertices_mm);
  lists_ = findMaterialNeighbours(rest_field, rest_.vertices_mm);
}

namespace {

/// Newton steps on g(p) = 0 for a field g, each halved until |g| drops; returns the final sample
/// (and g at p before the steps in start_value).
FieldSample projectOnto(const ImplicitField& g, Eigen::Vector3d& p, const SurfaceSettings& settings,
                        double& start_value) {
  FieldSample at = g.calcSample(p);
  start_value = at.value;
  for (int step = 0; step < settings.newton_steps && std::abs(at.value) > settings.tolerance; ++step) {
    const double n2 = at.gradient.squaredNorm();
    if (!(n2 > 1e-24)) break;
    Eigen::Vector3d delta = -at.value * at.gradient / n2;
    const double length = delta.norm();
    if (length > settings.max_step_mm) delta *= settings.max_step_mm / length;
    bool lowered = false;
    for (int halving = 0; halving < 8 && !lowered; ++halving, delta *= 0.5) {
      const FieldSample trial = g.calcSample(p + delta);
      if (std::abs(trial.value) < std::abs(at.value)) {
        p += delta;
        at = trial;
        lowered = true;
      }
    }
    if (!lowered) break;
  }
  return at;
}

/// From p on f = 0 (∇f there: `gradient`), where p lies inside a bone: the first point where
/// the ray into the muscle (along ∇f) leaves the bones: there s = 0 < f, the muscle's contact
/// patch seen from p. Sphere tracing (a step of |s|, the distance to the nearest bone surface,
/// cannot pass an exit), at most `max_exit_steps` steps. The exit is taken only within twice
/// p's depth: further on, the ray ran along or through the bone, and p has no place on the
/// contact patch (it is left in the bone, so it finds no surface). The nearest bone surface is
/// no substitute: deep in a thin bone it flips from one face to the other, and a vertex jumped
/// by 10 mm in one frame. A p outside the bones stays where it is.
void exitBoneIntoMuscle(const ImplicitField& field, const Eigen::Vector3d& gradient, const ImplicitField& bones,
                        Eigen::Vector3d& p, const SurfaceSettings& settings) {
  double s = bones.calcValue(p);
  if (!(s < 0.0) || !(gradient.squaredNorm() > 1e-24)) return;
  const Eigen::Vector3d inward = gradient.normalized();
  const double reach_mm = -2.0 * s + settings.tolerance;
  double t = 0.0;
  for (int step = 0; step < settings.max_exit_steps && t <= reach_mm; ++step) {
    if (s >= -settings.tolerance) {
      const Eigen::Vector3d q = p + t * inward;
      if (field.calcValue(q) > 0.0) p = q;
      return;
    }
    t += -s + 0.5 * settings.tolerance;
    s = bones.calcValue(p + t * inward);
  }
}

}  // namespace

void SurfaceStage::run(MuscleState& state, const FrameInput&) {
  TriangleMesh& surface = state.surface_M;
  surface.triangles = rest_.triangles;
  lattice_->carry(binding_, surface.vertices_mm);
  double residual = 0.0, depth = 0.0, start = 0.0;
  int unresolved = 0;
  found_.assign(static_cast<size_t>(surface.vertices_mm.cols()), 1);
  for (Eigen::Index v = 0; v < surface.vertices_mm.cols(); ++v) {
    const int j = static_cast<int>(v);
    Eigen::Vector3d p = surface.vertices_mm.col(v);
    // First onto the field's surface f = 0 (smooth), then, where that lies in a bone, onto the
    // bone's face on the muscle's side: the surface of min(f, s) is f = 0 outside the bones and
    // s = 0 on them.
    const MuscleShape field(state, lists_.begin(j), lists_.count(j), false);
    double start_value = 0.0;
    const FieldSample on_field = projectOnto(field, p, settings_, start_value);
    start = std::max(start, std::abs(start_value));
    const MuscleShape shape(state, lists_.begin(j), lists_.count(j));
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
