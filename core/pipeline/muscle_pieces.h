// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// A check, not a stage: how many pieces the muscle is in, counted on a grid.
#include "pipeline/muscle_state.h"

#include <Eigen/Core>

#include <limits>

namespace rbfmuscle {

/// The pieces of the muscle outside the bones, {min(f̃, s) > 0} (muscle_state.h).
struct MusclePieces {
  int pieces = 0;                  ///< connected pieces (0: the muscle vanished)
  double largest_volume_mm3 = 0;   ///< volume of the largest piece
  double stray_volume_mm3 = 0;     ///< volume of all the others
  /// Mean of the grid nodes of the largest piece but one (M, mm): the part that came off.
  /// NaN when the muscle is in one piece or none.
  Eigen::Vector3d stray_centre_mm = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
};

/// Counts the pieces of the state's muscle on the grid of nodes box.min() + cell_mm·(i, j, k)
/// that extractIsoSurface samples (iso_surface.h) over the box of the kernels with λ > 0: two
/// nodes inside are joined when an edge of that grid's tetrahedra joins them, as the extracted
/// surface joins them (a cavity is not a piece). A neck thinner than a cell falls between the
/// nodes and splits a piece in two, so around every piece but the largest (its nodes' box grown
/// by two cells) the grid is refined four times, and pieces the finer grid joins count as one;
/// a piece whose finer grid would hold more than 10⁸ nodes is not refined. A volume
/// is its nodes times cell_mm³. A piece thinner than a cell may still be missed. Costs a field
/// evaluation at every node (0.1–0.2 s for 2 mm cells over a hip muscle) and 64 at every node
/// of a stray piece's box: for tests and tools, never in a frame that is not asked to check.
/// @throws std::invalid_argument if cell_mm ≤ 0, the field's offset is > 0 (f > 0 far from
///   every kernel: no bounded muscle) or the grid would exceed 10⁹ nodes.
MusclePieces countMusclePieces(const MuscleState& state, double cell_mm);

}  // namespace rbfmuscle
