// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Putting a carried surface vertex onto a muscle's surface f = 0, and out of a bone onto the
/// bone's face towards the muscle.
///
/// Why a vertex the field holds inside goes out along its carried normal: the kernels' field
/// drifts from the tissue map's image of the rest surface as the map bends (docs/design.md), so
/// a carried vertex can start deep inside (f = 24 on the gluteus flexed to 112°). From there,
/// Newton steps along ∇f go to whichever face of a thin sheet is nearer, or slide sideways over a
/// shallow field, and from one frame to the next they reached faces 4–7 mm apart (the gluteus at
/// 112°–117°, the iliacus at 79°). The carried normal says which face is the vertex's own. A
/// vertex outside goes to the nearest surface by Newton steps: there the normal can run along
/// the surface, and the first crossing on it jumped by 7 mm where a bump of f = 0 vanished
/// (the iliacus at 74°, tried).
#include "rbf/implicit_field.h"

#include <Eigen/Core>

namespace rbfmuscle {

/// Settings of the tracked surface.
struct SurfaceSettings {
  int newton_steps = 10;         ///< projection steps per vertex at most, ≥ 1
  double tolerance = 1e-3;       ///< stop a vertex when |min(f, s)| ≤ this (field unit ≈ mm)
  double max_step_mm = 2.0;      ///< longest projection step (mm), > 0
  int max_exit_steps = 50;       ///< steps of the way out of a bone into the muscle at most, ≥ 1
};

/// Checks the settings. @throws std::invalid_argument naming what is wrong.
void checkSurfaceSettings(const SurfaceSettings& settings);

/// Newton steps on f(p) = 0 from p, where f's sample is `at`, each shortened to max_step_mm and
/// halved (at most 8 times) until |f| drops, at most newton_steps, until |f| ≤ tolerance; returns
/// the final sample.
FieldSample projectByNewton(const ImplicitField& f, FieldSample at, Eigen::Vector3d& p_mm, const SurfaceSettings& settings);

/// The first point where f changes sign on the ray from p along n (f(p) > 0, inside) or −n
/// (outside), within reach_mm of p (n unit): steps of the ray's own Newton step where f heads
/// for 0 along it, else of |f| (each 0.05 mm to max_step_mm), until the sign changes; then Newton
/// steps on the ray kept in that bracket by bisection, to |f| ≤ tolerance, at most 60 rounds.
/// `at` is f's sample at p on entry and at the point found on return. Returns false, p and `at`
/// unchanged, when f keeps its sign to reach_mm.
bool projectAlongLine(const ImplicitField& f, const Eigen::Vector3d& n, FieldSample& at, Eigen::Vector3d& p_mm,
                      const SurfaceSettings& settings, double reach_mm);

/// A carried vertex p with carried outward normal n (any length; 0: none) onto f = 0: from inside
/// (f(p) > 0) along n to the first crossing within newton_steps · max_step_mm, the Newton steps'
/// own reach; from outside, or where that ray finds no crossing, by the Newton steps (file
/// comment). Returns the sample there; start_value is f(p).
FieldSample projectVertex(const ImplicitField& f, const Eigen::Vector3d& n, Eigen::Vector3d& p_mm,
                          const SurfaceSettings& settings, double& start_value);

/// From p on f = 0 (∇f there: `gradient`), where p lies inside a bone: the first point where
/// the ray into the muscle (along ∇f) leaves the bones: there s = 0 < f, the muscle's contact
/// patch seen from p. Sphere tracing (a step of |s|, the distance to the nearest bone surface,
/// cannot pass an exit), at most `max_exit_steps` steps. The exit is taken only within twice
/// p's depth: further on, the ray ran along or through the bone, and p has no place on the
/// contact patch (it is left in the bone, so it finds no surface). The nearest bone surface is
/// no substitute: deep in a thin bone it flips from one face to the other, and a vertex jumped
/// by 10 mm in one frame. A p outside the bones stays where it is.
void exitBoneIntoMuscle(const ImplicitField& field, const Eigen::Vector3d& gradient, const ImplicitField& bones,
                        Eigen::Vector3d& p_mm, const SurfaceSettings& settings);

}  // namespace rbfmuscle
