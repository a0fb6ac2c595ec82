// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Uniform cell grid over a set of 3-D points for fixed-radius neighbour
/// queries: built once, updated cheaply when the points move.
#include <Eigen/Core>

#include <vector>

namespace rbfmuscle {

/// Dense uniform grid over the bounding box of points p_i (3×N, mm, any
/// frame), with the points sorted by cell (counting sort, CSR offsets), so a
/// row of cells along x is one contiguous range of points. Point i lies in
/// cell floor((p_i − o) / h) with o the box's lower corner and h the cell
/// edge: the requested size, enlarged when the box would need more than
/// max(8N, 32768) cells (memory stays O(N) however far apart the points are).
///
/// A query visits the rows of cells overlapping the cube of half-side R around
/// the query point and reports every point with ‖p_i − p‖² ≤ R², in ascending
/// index order. When the cube covers every cell, or visiting its rows would
/// cost more than testing every point, the query tests every point instead
/// (same result). Queries are const and thread-safe; build() and update() are not.
class SpatialGrid {
 public:
  /// An empty grid (no points); every query returns nothing.
  SpatialGrid() = default;
  /// Builds the grid: see build().
  SpatialGrid(const Eigen::Matrix3Xd& points_mm, double cell_size_mm);

  /// Indexes `points_mm` (3×N) with cells of edge ≥ `cell_size_mm`.
  /// @throws std::invalid_argument if the cell size is not finite and > 0, or
  ///   a point is not finite (the message names the point index and value).
  void build(const Eigen::Matrix3Xd& points_mm, double cell_size_mm);

  /// Re-indexes moved points with the requested cell size of build(): O(N +
  /// cells), and no allocation when the point count and box size do not grow.
  /// A different point count is allowed. Same exceptions as build().
  void update(const Eigen::Matrix3Xd& points_mm);

  /// Writes into `out` (cleared first, caller-owned so a warm vector does not
  /// allocate) the indices i with ‖p_i − p_mm‖² ≤ radius_mm², ascending.
  /// A negative or NaN radius yields nothing.
  /// @throws std::invalid_argument if `p_mm` is not finite.
  void findWithinRadius(const Eigen::Vector3d& p_mm, double radius_mm,
                        std::vector<int>& out) const;

  /// As findWithinRadius(), but the indices come in an order fixed by the
  /// points' cells (deterministic, not ascending) when the result is true;
  /// ascending when it is false. For callers that merge several lists and
  /// sort once.
  bool findWithinRadiusUnordered(const Eigen::Vector3d& p_mm, double radius_mm,
                                 std::vector<int>& out) const;

  /// Calls visit(i, p_i) for every point i in the cells overlapping the cube
  /// of half-side radius_mm around p_mm (a superset of the ball; no distance
  /// test), in an order fixed by the points' cells; or for every point when
  /// that is cheaper. For callers with their own per-point test.
  /// @return true when the visit went cell by cell, false when it went in
  ///   ascending index order (every point) or visited nothing.
  /// @throws std::invalid_argument if `p_mm` is not finite.
  template <class Visitor>
  bool visitCandidates(const Eigen::Vector3d& p_mm, double radius_mm, Visitor&& visit) const {
    int lo[3], hi[3];
    switch (findCellRange(p_mm, radius_mm, lo, hi)) {
      case CellRange::kNone:
        return false;
      case CellRange::kAll:
        for (Eigen::Index i = 0; i < points_mm_.cols(); ++i)
          visit(static_cast<int>(i), points_mm_.col(i));
        return false;
      case CellRange::kCells:
        break;
    }
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y) {
        const std::size_t row = static_cast<std::size_t>(z * dims_[1] + y) * dims_[0];
        const int end = cell_start_[row + static_cast<std::size_t>(hi[0]) + 1];
        for (int k = cell_start_[row + static_cast<std::size_t>(lo[0])]; k < end; ++k)
          visit(sorted_index_[static_cast<std::size_t>(k)], sorted_points_mm_.col(k));
      }
    return true;
  }

  /// Number of indexed points N.
  int getNumPoints() const { return static_cast<int>(points_mm_.cols()); }
  /// Cell edge h in use (mm): the requested size or larger (see class comment).
  double getCellSize() const { return cell_size_mm_; }
  /// The indexed points (3×N, mm), in their original order.
  const Eigen::Matrix3Xd& getPoints() const { return points_mm_; }

 private:
  /// Computes the box, the cell size and the dimensions, then sorts the points
  /// into cells.
  void index();
  /// What a query must visit: nothing, every point, or the cells lo..hi.
  enum class CellRange { kNone, kAll, kCells };
  /// Cells overlapping the cube of half-side radius_mm around p_mm, clamped to
  /// the box, or kAll when testing every point is cheaper.
  CellRange findCellRange(const Eigen::Vector3d& p_mm, double radius_mm, int lo[3],
                          int hi[3]) const;

  double requested_cell_size_mm_ = 1.0;
  double cell_size_mm_ = 1.0;
  Eigen::Vector3d origin_mm_ = Eigen::Vector3d::Zero();  ///< lower corner of the box
  Eigen::Vector3i dims_ = Eigen::Vector3i::Zero();       ///< cells per axis
  Eigen::Matrix3Xd points_mm_;                           ///< original order
  Eigen::Matrix3Xd sorted_points_mm_;                    ///< sorted by cell
  std::vector<int> sorted_index_;                        ///< original index of each sorted point
  std::vector<int> point_cell_;                          ///< linear cell of each point
  std::vector<int> cell_start_;                          ///< CSR offsets, size = cells + 1
};

}  // namespace rbfmuscle
