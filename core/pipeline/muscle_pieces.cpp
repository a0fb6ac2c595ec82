// SPDX-License-Identifier: Apache-2.0
#include "pipeline/muscle_pieces.h"

#include "geometry/disjoint_sets.h"
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

/// The finer grid around a stray piece: 4× finer, 0.5 mm for the scenes' 2 mm cells, where a
/// 2 mm grid splits the psoas's tendon beside the lesser trochanter and a 1 mm grid does not.
constexpr int kRefinement = 4;
/// Cells by which the finer grid reaches past a stray piece's nodes.
constexpr std::int64_t kMarginCells = 2;
/// Most nodes of one finer grid: 10⁸ (0.5 GB of flags and labels). At 2 mm cells that is a
/// stray piece's box of about 230 mm a side.
constexpr std::int64_t kMaxFineNodes = 100'000'000;

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

/// Marks the nodes origin + cell_mm·(i, j, k), i < n₀, j < n₁, k < n₂, inside the muscle
/// (flags indexed as labelGridPieces reads them), a layer at a time.
std::vector<char> markInside(const MuscleState& state, const Eigen::Vector3d& origin, double cell_mm,
                             const std::array<std::int64_t, 3>& n) {
  const std::int64_t layer = n[0] * n[1];
  std::vector<char> inside(static_cast<std::size_t>(layer * n[2]), 0);
  Eigen::Matrix3Xd points(3, layer);
  Eigen::VectorXd values;
  for (std::int64_t k = 0; k < n[2]; ++k) {
    for (std::int64_t j = 0; j < n[1]; ++j)
      for (std::int64_t i = 0; i < n[0]; ++i)
        points.col(i + n[0] * j) = origin + cell_mm * Eigen::Vector3d(double(i), double(j), double(k));
    state.field.calcValues(points, values);  // parallel
    for (std::int64_t v = 0; v < layer; ++v) {  // the muscle, without f's gradient
      const FieldSample f{values[v], Eigen::Vector3d::Zero()};
      inside[static_cast<std::size_t>(v + layer * k)] = applyBones(state, points.col(v), f, BoneContact::kFolded).value > 0.0;
    }
  }
  return inside;
}

/// Index box (lowest, highest node) of a piece's nodes, and the sum of their indices.
struct NodeBox {
  std::array<std::int64_t, 3> lo{}, hi{};
  Eigen::Vector3d index_sum = Eigen::Vector3d::Zero();
};

std::vector<NodeBox> findPieceBoxes(const GridPieces& labelled, const std::array<std::int64_t, 3>& n) {
  std::vector<NodeBox> boxes(labelled.nodes_of_piece.size(), NodeBox{n, {0, 0, 0}});
  for (std::int64_t v = 0; v < n[0] * n[1] * n[2]; ++v) {
    const int piece = labelled.piece_of_node[std::size_t(v)];
    if (piece < 0) continue;
    const std::array<std::int64_t, 3> ijk = splitNodeIndex(v, n);
    NodeBox& box = boxes[std::size_t(piece)];
    for (int a = 0; a < 3; ++a) {
      box.lo[a] = std::min(box.lo[a], ijk[a]), box.hi[a] = std::max(box.hi[a], ijk[a]);
      box.index_sum[a] += double(ijk[a]);
    }
  }
  return boxes;
}

/// Joins the pieces that a grid kRefinement times finer joins over `around`, a piece's node box
/// grown by kMarginCells (the neck between two pieces lies next to both).
void joinThroughFinerGrid(const MuscleState& state, const Eigen::Vector3d& origin, double cell_mm,
                          const std::array<std::int64_t, 3>& n, const GridPieces& labelled, const NodeBox& around,
                          DisjointSets& joined) {
  std::array<std::int64_t, 3> lo = around.lo, hi = around.hi;
  std::array<std::int64_t, 3> fine_n{};
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::max<std::int64_t>(0, lo[a] - kMarginCells);
    hi[a] = std::min<std::int64_t>(n[a] - 1, hi[a] + kMarginCells);
    fine_n[a] = (hi[a] - lo[a]) * kRefinement + 1;
  }
  if (fine_n[0] * fine_n[1] * fine_n[2] > kMaxFineNodes) return;
  const Eigen::Vector3d fine_origin = origin + cell_mm * Eigen::Vector3d(double(lo[0]), double(lo[1]), double(lo[2]));
  const GridPieces fine = labelGridPieces(markInside(state, fine_origin, cell_mm / kRefinement, fine_n), fine_n);
  // The grid's nodes are nodes of the finer grid: pieces whose nodes share a finer piece are one.
  std::vector<int> first_of_fine(fine.nodes_of_piece.size(), -1);
  for (std::int64_t k = lo[2]; k <= hi[2]; ++k)
    for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
      for (std::int64_t i = lo[0]; i <= hi[0]; ++i) {
        const int coarse = labelled.piece_of_node[std::size_t(i + n[0] * (j + n[1] * k))];
        const std::int64_t f = (i - lo[0]) * kRefinement + fine_n[0] * ((j - lo[1]) * kRefinement + fine_n[1] * (k - lo[2]) * kRefinement);
        const int fine_piece = fine.piece_of_node[std::size_t(f)];
        if (coarse < 0 || fine_piece < 0) continue;
        int& first = first_of_fine[std::size_t(fine_piece)];
        if (first < 0) first = coarse;
        else joined.join(first, coarse);
      }
}

/// Mean of the nodes of the second largest joined piece (the first of equals), as an index.
Eigen::Vector3d findStrayCentre(const std::vector<NodeBox>& boxes, DisjointSets& joined,
                                const std::vector<std::int64_t>& nodes_of_joined) {
  const auto largest_after = [&](int skip) {
    int best = -1;
    for (int p = 0; p < static_cast<int>(nodes_of_joined.size()); ++p)
      if (p != skip && (best < 0 || nodes_of_joined[size_t(p)] > nodes_of_joined[size_t(best)])) best = p;
    return best;
  };
  const int stray = largest_after(largest_after(-1));
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int p = 0; p < static_cast<int>(boxes.size()); ++p)
    if (joined.find(p) == stray) sum += boxes[size_t(p)].index_sum;
  return sum / double(nodes_of_joined[size_t(stray)]);
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
  const GridPieces labelled = labelGridPieces(markInside(state, box.min(), cell_mm, n), n);
  const int largest = labelled.findLargest();
  DisjointSets joined(labelled.nodes_of_piece.size());
  const std::vector<NodeBox> piece_boxes = findPieceBoxes(labelled, n);
  for (int p = 0; p < static_cast<int>(labelled.nodes_of_piece.size()); ++p)
    if (p != largest) joinThroughFinerGrid(state, box.min(), cell_mm, n, labelled, piece_boxes[std::size_t(p)], joined);
  std::vector<std::int64_t> nodes_of_joined(labelled.nodes_of_piece.size(), 0);
  std::int64_t total = 0;
  for (int p = 0; p < static_cast<int>(labelled.nodes_of_piece.size()); ++p) {
    nodes_of_joined[std::size_t(joined.find(p))] += labelled.nodes_of_piece[std::size_t(p)];
    total += labelled.nodes_of_piece[std::size_t(p)];
  }
  const std::int64_t largest_nodes =
      nodes_of_joined.empty() ? 0 : *std::max_element(nodes_of_joined.begin(), nodes_of_joined.end());
  result.pieces = static_cast<int>(std::count_if(nodes_of_joined.begin(), nodes_of_joined.end(), [](std::int64_t c) { return c > 0; }));
  const double node_mm3 = cell_mm * cell_mm * cell_mm;
  result.largest_volume_mm3 = double(largest_nodes) * node_mm3;
  result.stray_volume_mm3 = double(total - largest_nodes) * node_mm3;
  if (result.pieces > 1)
    result.stray_centre_mm = box.min() + cell_mm * findStrayCentre(piece_boxes, joined, nodes_of_joined);
  return result;
}

}  // namespace rbfmuscle
