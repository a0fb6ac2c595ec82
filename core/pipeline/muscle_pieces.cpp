// SPDX-License-Identifier: Apache-2.0
#include "pipeline/muscle_pieces.h"

#include "geometry/grid_pieces.h"
#include "geometry/iso_surface.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace rbfmuscle {
namespace {

/// Where f can be > 0: the union of the cut-off boxes of the kernels with λ > 0 (elsewhere
/// f ≤ b plus the negative kernels, and b ≤ 0).
Eigen::AlignedBox3d findPositiveKernelBox(const DeformedField& field) {
  Eigen::AlignedBox3d box;
  for (int k = 0; k < field.getNumKernels(); ++k) {
    if (field.getWeights()[k] <= 0.0) continue;
    const Eigen::Vector3d half = field.calcHalfExtents(k), centre = field.getCentres().col(k);
    box.extend(centre - half);
    box.extend(centre + half);
  }
  return box;
}

}  // namespace

MusclePieces countMusclePieces(const MuscleState& state, double cell_mm) {
  if (!(cell_mm > 0.0)) throw std::invalid_argument("countMusclePieces: cell " + std::to_string(cell_mm) + " mm; expected > 0");
  if (state.field.getOffset() > 0.0)
    throw std::invalid_argument("countMusclePieces: the field's offset is " + std::to_string(state.field.getOffset()) +
                                " > 0, so f > 0 far from every kernel: the muscle is not bounded");
  const Eigen::AlignedBox3d box = findPositiveKernelBox(state.field);
  MusclePieces result;
  if (box.isEmpty()) return result;
  checkIsoSurfaceGrid(box, cell_mm);
  const std::array<std::int64_t, 3> n = countIsoSurfaceNodes(box, cell_mm);
  const std::int64_t layer = n[0] * n[1];
  std::vector<char> inside(static_cast<std::size_t>(layer * n[2]), 0);
  Eigen::Matrix3Xd points(3, layer);
  Eigen::VectorXd values;
  for (std::int64_t k = 0; k < n[2]; ++k) {
    for (std::int64_t j = 0; j < n[1]; ++j)
      for (std::int64_t i = 0; i < n[0]; ++i)
        points.col(i + n[0] * j) = box.min() + cell_mm * Eigen::Vector3d(double(i), double(j), double(k));
    state.field.calcValues(points, values);  // parallel
    for (std::int64_t v = 0; v < layer; ++v) {  // the muscle, without f's gradient
      const FieldSample f{values[v], Eigen::Vector3d::Zero()};
      inside[static_cast<std::size_t>(v + layer * k)] = applyBones(state, points.col(v), f, BoneContact::kFolded).value > 0.0;
    }
  }
  const GridPieces labelled = labelGridPieces(inside, n);
  std::int64_t total = 0;
  for (std::int64_t count : labelled.nodes_of_piece) total += count;
  const int largest = labelled.findLargest();
  result.pieces = static_cast<int>(labelled.nodes_of_piece.size());
  const std::int64_t largest_nodes = largest < 0 ? 0 : labelled.nodes_of_piece[std::size_t(largest)];
  const double node_mm3 = cell_mm * cell_mm * cell_mm;
  result.largest_volume_mm3 = double(largest_nodes) * node_mm3;
  result.stray_volume_mm3 = double(total - largest_nodes) * node_mm3;
  return result;
}

}  // namespace rbfmuscle
