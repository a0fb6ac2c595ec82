#pragma once
/// @file
/// Uniform hashed grid over a set of 3-D points for fixed-radius neighbour
/// queries: built once, updated cheaply when the points move.
#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace rbfmuscle {

/// Hashed uniform grid over points p_i (3×N, mm, any frame). Point i lies in
/// cell c = floor(p_i / h) (componentwise, h = cell size in mm); cells map to
/// a power-of-two bucket table (≥ 2N buckets) stored compactly (CSR), so the
/// memory is O(N) however far apart the points are.
///
/// A query visits the cells overlapping the cube of half-side R around the
/// query point and reports every point with ‖p_i − p‖² ≤ R², in ascending
/// index order. When that cube covers more cells than there are points, the
/// query scans all points instead (same result). Queries are const and
/// thread-safe; build() and update() are not.
class SpatialGrid {
 public:
  /// An empty grid (no points, cell size 1 mm); every query returns nothing.
  SpatialGrid() = default;
  /// Builds the grid: see build().
  SpatialGrid(const Eigen::Matrix3Xd& points_mm, double cell_size_mm);

  /// Indexes `points_mm` (3×N) with cells of edge `cell_size_mm`.
  /// @throws std::invalid_argument if the cell size is not finite and > 0, or
  ///   a point coordinate is not finite or too large for the cell size
  ///   (|x/h| ≥ 1e15); the message names the point index and value.
  void build(const Eigen::Matrix3Xd& points_mm, double cell_size_mm);

  /// Re-indexes moved points, keeping the cell size: O(N), and no allocation
  /// when the point count is unchanged; returns at once (after the cell
  /// computation) when no point changed cell. A different point count
  /// rebuilds. Same exceptions as build().
  void update(const Eigen::Matrix3Xd& points_mm);

  /// Writes into `out` (cleared first, caller-owned so a warm vector does not
  /// allocate) the indices i with ‖p_i − p_mm‖² ≤ radius_mm², ascending.
  /// A negative or NaN radius yields nothing.
  /// @throws std::invalid_argument if `p_mm` is not finite.
  void findWithinRadius(const Eigen::Vector3d& p_mm, double radius_mm,
                        std::vector<int>& out) const;

  /// Number of indexed points N.
  int getNumPoints() const { return static_cast<int>(points_mm_.cols()); }
  /// Cell edge h (mm).
  double getCellSize() const { return cell_size_mm_; }
  /// The indexed points (3×N, mm), as last given to build() or update().
  const Eigen::Matrix3Xd& getPoints() const { return points_mm_; }

 private:
  using Cell = Eigen::Matrix<std::int64_t, 3, 1>;

  /// Computes cells_ from points_mm_; returns true if any cell changed.
  bool computeCells();
  /// Rebuilds the bucket table (CSR) from cells_.
  void fillBuckets();
  /// Bucket index of a cell.
  std::size_t findBucket(const Cell& cell) const;
  /// Brute-force scan of all points (ascending by construction).
  void scanAll(const Eigen::Vector3d& p_mm, double radius_sq_mm2, std::vector<int>& out) const;

  double cell_size_mm_ = 1.0;
  Eigen::Matrix3Xd points_mm_;
  std::vector<Cell> cells_;                 ///< cell of each point
  std::vector<int> bucket_start_;           ///< CSR offsets, size = buckets + 1
  std::vector<int> bucket_points_;          ///< point indices grouped by bucket, ascending in each
  std::vector<int> fill_cursor_;            ///< scratch for fillBuckets()
  std::size_t bucket_mask_ = 0;             ///< bucket count − 1 (power of two)
};

}  // namespace rbfmuscle
