// SPDX-License-Identifier: Apache-2.0
#include "rbf/spatial_grid.h"

#include "rbf/ascending_indices.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace rbfmuscle {

namespace {

/// Cells allowed per point (and at least kMinCellBudget in all).
constexpr double kCellsPerPoint = 8.0;
constexpr double kMinCellBudget = 32768.0;
/// Cost of visiting one row of cells, in units of one point test: above
/// rows · kRowCost > N a query tests every point instead.
constexpr double kRowCost = 8.0;
/// Growth of the cell edge per try when the box needs too many cells, and the
/// cap on tries (the cell count falls by ≥ 1.1³ per try).
constexpr double kCellGrowth = 1.1;
constexpr int kMaxCellTries = 400;

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
  requested_cell_size_mm_ = cell_size_mm;
  update(points_mm);
}

void SpatialGrid::update(const Eigen::Matrix3Xd& points_mm) {
  for (Eigen::Index i = 0; i < points_mm.cols(); ++i)
    if (!points_mm.col(i).allFinite()) {
      std::ostringstream s;
      s << "SpatialGrid: point " << i << " = (" << points_mm.col(i).transpose()
        << ") mm, expected finite coordinates";
      throw std::invalid_argument(s.str());
    }
  points_mm_ = points_mm;
  index();
}

void SpatialGrid::index() {
  const Eigen::Index n = points_mm_.cols();
  cell_size_mm_ = requested_cell_size_mm_;
  if (n == 0) {
    dims_.setZero();
    cell_start_.assign(1, 0);
    sorted_index_.clear();
    point_cell_.clear();
    sorted_points_mm_.resize(3, 0);
    return;
  }
  origin_mm_ = points_mm_.rowwise().minCoeff();
  const Eigen::Vector3d extent = points_mm_.rowwise().maxCoeff() - origin_mm_;
  if (!extent.allFinite()) {
    std::ostringstream s;
    s << "SpatialGrid: points span (" << extent.transpose()
      << ") mm, expected a finite bounding box";
    throw std::invalid_argument(s.str());
  }
  // At most 1e6 cells per axis to start with, then grow until within budget.
  cell_size_mm_ = std::max(cell_size_mm_, extent.maxCoeff() * 1e-6);
  const double budget = std::max(kCellsPerPoint * static_cast<double>(n), kMinCellBudget);
  Eigen::Vector3d dims;
  for (int tries = 0;; ++tries) {
    dims = (extent / cell_size_mm_).array().floor() + 1.0;
    if (dims.prod() <= budget) break;
    if (tries == kMaxCellTries) {
      std::ostringstream s;
      s << "SpatialGrid: no cell size up to " << cell_size_mm_ << " mm fits box ("
        << extent.transpose() << ") mm into " << budget << " cells";
      throw std::runtime_error(s.str());
    }
    cell_size_mm_ *= std::max(kCellGrowth, std::cbrt(dims.prod() / budget));
  }
  dims_ = dims.cast<int>();
  const double inv_h = 1.0 / cell_size_mm_;
  const int cells = dims_.prod();
  cell_start_.assign(static_cast<std::size_t>(cells) + 1, 0);
  point_cell_.resize(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) {
    int c[3];
    for (int a = 0; a < 3; ++a)
      c[a] = std::min(static_cast<int>((points_mm_(a, i) - origin_mm_[a]) * inv_h), dims_[a] - 1);
    const int cell = (c[2] * dims_[1] + c[1]) * dims_[0] + c[0];
    point_cell_[static_cast<std::size_t>(i)] = cell;
    ++cell_start_[static_cast<std::size_t>(cell) + 1];
  }
  for (int c = 0; c < cells; ++c)
    cell_start_[static_cast<std::size_t>(c) + 1] += cell_start_[static_cast<std::size_t>(c)];
  // Counting sort, stable (ascending index within a cell): place with a
  // running cursor in cell_start_, then shift the cursors back to starts.
  sorted_index_.resize(static_cast<std::size_t>(n));
  sorted_points_mm_.resize(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const int slot = cell_start_[static_cast<std::size_t>(point_cell_[static_cast<std::size_t>(i)])]++;
    sorted_index_[static_cast<std::size_t>(slot)] = static_cast<int>(i);
    sorted_points_mm_.col(slot) = points_mm_.col(i);
  }
  for (int c = cells; c > 0; --c)
    cell_start_[static_cast<std::size_t>(c)] = cell_start_[static_cast<std::size_t>(c) - 1];
  cell_start_[0] = 0;
}

void SpatialGrid::findWithinRadius(const Eigen::Vector3d& p_mm, double radius_mm,
                                   std::vector<int>& out) const {
  if (findWithinRadiusUnordered(p_mm, radius_mm, out))
    sortAscendingIndices(out, static_cast<int>(points_mm_.cols()));
}

bool SpatialGrid::findWithinRadiusUnordered(const Eigen::Vector3d& p_mm, double radius_mm,
                                            std::vector<int>& out) const {
  out.clear();
  const double radius_sq = radius_mm * radius_mm;
  return visitCandidates(p_mm, radius_mm, [&](int i, const auto& p_i) {
    if ((p_i - p_mm).squaredNorm() <= radius_sq) out.push_back(i);
  });
}

SpatialGrid::CellRange SpatialGrid::findCellRange(const Eigen::Vector3d& p_mm, double radius_mm,
                                                  int lo[3], int hi[3]) const {
  if (!p_mm.allFinite()) {
    std::ostringstream s;
    s << "SpatialGrid: query point (" << p_mm.transpose() << ") mm, expected finite coordinates";
    throw std::invalid_argument(s.str());
  }
  if (!(radius_mm >= 0.0) || points_mm_.cols() == 0) return CellRange::kNone;
  const double inv_h = 1.0 / cell_size_mm_;
  // Cells overlapping the query cube, clamped to the box; doubles until
  // clamped, so far queries cannot overflow.
  bool covers_all = true;
  for (int a = 0; a < 3; ++a) {
    // A relative margin keeps points whose distance test passes only through
    // rounding inside the visited cells.
    const double reach =
        radius_mm + 1e-9 * (radius_mm + std::abs(p_mm[a]) + std::abs(origin_mm_[a]) + cell_size_mm_);
    const double first = std::floor((p_mm[a] - reach - origin_mm_[a]) * inv_h);
    const double last = std::floor((p_mm[a] + reach - origin_mm_[a]) * inv_h);
    if (last < 0.0 || first > dims_[a] - 1.0) return CellRange::kNone;  // misses the box
    covers_all = covers_all && first <= 0.0 && last >= dims_[a] - 1.0;
    lo[a] = static_cast<int>(std::max(first, 0.0));
    hi[a] = static_cast<int>(std::min(last, dims_[a] - 1.0));
  }
  const double rows = (hi[1] - lo[1] + 1.0) * (hi[2] - lo[2] + 1.0);
  if (covers_all || rows * kRowCost > static_cast<double>(points_mm_.cols())) return CellRange::kAll;
  return CellRange::kCells;
}

}  // namespace rbfmuscle
