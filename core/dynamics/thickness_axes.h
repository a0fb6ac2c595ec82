// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Where a rest point lies across the muscle's thickness: the direction through the muscle
/// and the point's offset from the mid-surface along it.
///
/// Why: muscle is incompressible, but the bone blend that carries it is not (it lengthens a
/// flexed gluteus maximus by about 40 % without thinning it). TissueLattice thins the tissue by
/// the blend's own volume change J across this direction, about the mid-surface (or about an
/// end of the chord that lies on a bone), so that neighbouring kernels move together as they
/// thin and the muscle keeps one piece. Lowering the field everywhere (the weights, or the
/// offset) instead moves the surface inward by the same amount everywhere, and breaks the thin
/// parts first: the gluteus at 80° flexion fell into three pieces before it reached its rest
/// volume.
#include "geometry/mesh_distance.h"

#include <Eigen/Core>

namespace rbfmuscle {

/// Thickness axis and mid-surface offset of each point.
struct ThicknessAxes {
  Eigen::Matrix3Xd axes;         ///< n (3×P, unit): from the nearest surface point into the muscle
  Eigen::VectorXd offsets_mm;    ///< (x − m)·n (P, mm): signed distance from the mid-surface point m
  Eigen::VectorXd half_chords_mm;  ///< h (P, mm): half the chord, so q = m − h n and the exit is m + h n
};

/// For each point x (3×P, mm, the mesh's frame): q its closest point on the closed muscle
/// surface, n the unit direction from q into the muscle (towards x when x is inside, away
/// from x when outside; inside by the generalised winding number), and m the midpoint of the chord from q along n to where the ray
/// leaves the muscle (found by 1 mm steps, then bisection to 0.01 mm; capped at the mesh's
/// box diagonal). A point on the surface with no direction gets n = the surface's inward
/// direction from the pseudo-normal test, offset −chord/2.
/// @throws std::invalid_argument if a point is not finite.
ThicknessAxes calcThicknessAxes(const MeshDistance& muscle_surface, const Eigen::Matrix3Xd& points_mm);

}  // namespace rbfmuscle
