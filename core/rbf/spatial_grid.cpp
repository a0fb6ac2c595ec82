#include "rbf/spatial_grid.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace rbfmuscle {

namespace {

/// Cell coordinates beyond this magnitude cannot be converted to int64 safely
/// (and would lose all precision anyway).
constexpr double kMaxCellCoordinate = 1e15;

}  // namespace

SpatialGrid::SpatialGrid(const Eigen::Matrix3Xd& points_mm, double cell_size_mm) {
  build(points_mm, cell_size_mm);
}

void SpatialGrid::build(const Eigen::Matrix3Xd& points_mm, double cell_size_mm) {
  if (!(std::isfinite(cell_size_mm) && cell_size_mm > 0.0)) {
    std::ostringstream s;
    s << "SpatialGrid::build: cell size " << cell_size_mm << " mm, expected a finite value > 0";
    throw std::invalid_argument(s.str());
  }
  cell_size_mm_ = cell_size_mm;
  points_mm_ = points_mm;
  const std::size_t n = static_cast<std::size_t>(points_mm_.cols());
  cells_.assign(n, Cell::Zero());
  std::size_t buckets = 1;
  while (buckets < 2 * n) buckets <<= 1;
  bucket_mask_ = buckets - 1;
  bucket_start_.assign(buckets + 1, 0);
  bucket_points_.assign(n, 0);
  fill_cursor_.assign(buckets, 0);
  computeCells();
  fillBuckets();
}

void SpatialGrid::update(const Eigen::Matrix3Xd& points_mm) {
  if (points_mm.cols() != points_mm_.cols()) {
    build(points_mm, cell_size_mm_);
    return;
  }
  points_mm_ = points_mm;
  if (computeCells()) fillBuckets();
}

bool SpatialGrid::computeCells() {
  const double inv_h = 1.0 / cell_size_mm_;
  bool changed = false;
  for (Eigen::Index i = 0; i < points_mm_.cols(); ++i) {
    Cell c;
    for (int a = 0; a < 3; ++a) {
      const double x = points_mm_(a, i) * inv_h;
      if (!(std::abs(x) < kMaxCellCoordinate)) {
        std::ostringstream s;
        s << "SpatialGrid: point " << i << " coordinate " << a << " = " << points_mm_(a, i)
          << " mm, expected a finite value with |x / cell size| < 1e15 (cell size "
          << cell_size_mm_ << " mm)";
        throw std::invalid_argument(s.str());
      }
      c[a] = static_cast<std::int64_t>(std::floor(x));
    }
    if (c != cells_[static_cast<std::size_t>(i)]) {
      cells_[static_cast<std::size_t>(i)] = c;
      changed = true;
    }
  }
  return changed;
}

std::size_t SpatialGrid::findBucket(const Cell& cell) const {
  // Teschner et al. (2003) spatial hash, on 64-bit unsigned arithmetic.
  const auto x = static_cast<std::uint64_t>(cell[0]) * 73856093ULL;
  const auto y = static_cast<std::uint64_t>(cell[1]) * 19349663ULL;
  const auto z = static_cast<std::uint64_t>(cell[2]) * 83492791ULL;
  std::uint64_t h = x ^ y ^ z;
  h ^= h >> 29;
  return static_cast<std::size_t>(h) & bucket_mask_;
}

void SpatialGrid::fillBuckets() {
  std::fill(bucket_start_.begin(), bucket_start_.end(), 0);
  for (const Cell& c : cells_) ++bucket_start_[findBucket(c) + 1];
  for (std::size_t b = 0; b + 1 < bucket_start_.size(); ++b)
    bucket_start_[b + 1] += bucket_start_[b];
  std::copy(bucket_start_.begin(), bucket_start_.end() - 1, fill_cursor_.begin());
  for (std::size_t i = 0; i < cells_.size(); ++i)
    bucket_points_[static_cast<std::size_t>(fill_cursor_[findBucket(cells_[i])]++)] =
        static_cast<int>(i);
}

void SpatialGrid::scanAll(const Eigen::Vector3d& p_mm, double radius_sq_mm2,
                          std::vector<int>& out) const {
  for (Eigen::Index i = 0; i < points_mm_.cols(); ++i)
    if ((points_mm_.col(i) - p_mm).squaredNorm() <= radius_sq_mm2)
      out.push_back(static_cast<int>(i));
}

void SpatialGrid::findWithinRadius(const Eigen::Vector3d& p_mm, double radius_mm,
                                   std::vector<int>& out) const {
  out.clear();
  if (!p_mm.allFinite()) {
    std::ostringstream s;
    s << "SpatialGrid::findWithinRadius: query point (" << p_mm.transpose()
      << ") mm, expected finite coordinates";
    throw std::invalid_argument(s.str());
  }
  if (!(radius_mm >= 0.0) || points_mm_.cols() == 0) return;
  const double radius_sq = radius_mm * radius_mm;
  const double inv_h = 1.0 / cell_size_mm_;
  double lo[3], hi[3];
  double cell_count = 1.0;
  bool far = false;
  for (int a = 0; a < 3; ++a) {
    // A relative margin keeps points whose distance test passes only through
    // rounding inside the visited cells.
    const double reach = radius_mm + 1e-9 * (radius_mm + std::abs(p_mm[a]) + cell_size_mm_);
    lo[a] = std::floor((p_mm[a] - reach) * inv_h);
    hi[a] = std::floor((p_mm[a] + reach) * inv_h);
    far = far || !(std::abs(lo[a]) < kMaxCellCoordinate && std::abs(hi[a]) < kMaxCellCoordinate);
    cell_count *= hi[a] - lo[a] + 1.0;
  }
  if (far || cell_count > static_cast<double>(points_mm_.cols())) {
    scanAll(p_mm, radius_sq, out);
    return;
  }
  Cell c;
  for (c[2] = static_cast<std::int64_t>(lo[2]); c[2] <= static_cast<std::int64_t>(hi[2]); ++c[2])
    for (c[1] = static_cast<std::int64_t>(lo[1]); c[1] <= static_cast<std::int64_t>(hi[1]);
         ++c[1])
      for (c[0] = static_cast<std::int64_t>(lo[0]); c[0] <= static_cast<std::int64_t>(hi[0]);
           ++c[0]) {
        const std::size_t b = findBucket(c);
        for (int k = bucket_start_[b]; k < bucket_start_[b + 1]; ++k) {
          const int i = bucket_points_[static_cast<std::size_t>(k)];
          // Bucket collisions: accept only points of this very cell, so no
          // point is reported twice.
          if (cells_[static_cast<std::size_t>(i)] != c) continue;
          if ((points_mm_.col(i) - p_mm).squaredNorm() <= radius_sq) out.push_back(i);
        }
      }
  std::sort(out.begin(), out.end());
}

}  // namespace rbfmuscle
